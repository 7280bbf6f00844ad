// The area tool: the held points under the polygon, measured.
#include "viewer/area_tool.hpp"

#include <algorithm>
#include <vector>

#include "core/error.hpp"

namespace lidarscout::viewer {

recon::AreaVolume measure_area(const SceneSnapshot& snapshot, std::span<const PickedPoint> polygon,
                               const PointFilter& filter) {
    std::vector<recon::Point3> ring;
    dataset::Bounds box;
    for (const auto& p : polygon) {
        ring.push_back({p.x, p.y, p.z});
        box.min_x = std::min(box.min_x, p.x), box.max_x = std::max(box.max_x, p.x);
        box.min_y = std::min(box.min_y, p.y), box.max_y = std::max(box.max_y, p.y);
    }
    std::vector<recon::Point3> points;
    for (const auto& block : snapshot.full_points) {
        const auto& b = block->bounds;
        if (b.max_x < box.min_x || b.min_x > box.max_x || b.max_y < box.min_y || b.min_y > box.max_y) continue;
        const PointSet& set = block->points;
        for (const auto& a : set.points) {
            if (!filter.keeps_drawn(a.classification, a.returns, a.intensity)) continue;
            const double x = set.origin_x + a.dx, y = set.origin_y + a.dy;
            if (x < box.min_x || x > box.max_x || y < box.min_y || y > box.max_y) continue;
            points.push_back({x, y, set.origin_z + a.dz});
        }
    }
    return recon::measure_area_volume(ring, points);
}

std::string area_line(const SceneSnapshot& snapshot, std::span<const PickedPoint> polygon, const PointFilter& filter) {
    try {
        return "area: " + recon::area_volume_summary(measure_area(snapshot, polygon, filter));
    } catch (const Error& e) {
        return std::string("area: ") + e.what();
    }
}

}  // namespace lidarscout::viewer
