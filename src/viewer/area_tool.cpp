// The area tool: the polygon's points read as clip reads them, placed in world metres and measured.
#include "viewer/area_tool.hpp"

#include <atomic>
#include <vector>

#include "core/error.hpp"
#include "core/polygon.hpp"

namespace lidarscout::viewer {

pipelines::Region area_region(const dataset::Dataset& ds, std::span<const PickedPoint> polygon) {
    const double f = ds.frame.xy_to_metres;
    Ring ring;
    for (const auto& v : polygon) ring.push_back({v.x / f, v.y / f});
    return pipelines::polygon_region(MultiPolygon({{ring}}));
}

namespace {

// The points of `region` that `filter` keeps (read as clip reads them), in world metres; at most
// kMaxAreaPoints (the read stops past them: `over` set).
std::vector<recon::Point3> region_points_in_metres(const dataset::Dataset& ds, const pipelines::Region& region,
                                                   const PointFilter& filter, ThreadPool& pool,
                                                   const pipelines::ReadWatch& watch, bool& over) {
    std::atomic<bool> stop{false};
    pipelines::ReadWatch ours = watch;  // the caller's progress, and its cancel or ours
    ours.cancel = &stop;
    ours.progress = [&](std::uint64_t done, std::uint64_t total) {
        if (watch.cancelled()) stop = true;
        if (watch.progress) watch.progress(done, total);
    };
    const double f = ds.frame.xy_to_metres, fz = ds.frame.z_to_metres;
    std::vector<recon::Point3> points;
    const auto stats = pipelines::read_region_points(
        ds, pipelines::tiles_touching(ds, region), region, filter, pool,
        [&](const pipelines::RegionBatch& b) {
            if (points.size() + b.points.size() > kMaxAreaPoints) {
                over = stop = true;
                return;
            }
            for (const auto& p : b.points) points.push_back({p.x * f, p.y * f, p.z * fz});
        },
        ours);
    if (stats.cancelled && !over) throw Error::in_stage("measure", "cancelled");
    return points;
}

}  // namespace

recon::AreaVolume measure_area(const dataset::Dataset& ds, std::span<const PickedPoint> polygon,
                               const PointFilter& filter, ThreadPool& pool, const pipelines::ReadWatch& watch) {
    if (polygon.size() < 3) return recon::measure_area_volume({}, {});  // (its error: too few vertices)
    bool over = false;
    const auto points = region_points_in_metres(ds, area_region(ds, polygon), filter, pool, watch, over);
    if (over) {
        throw Error::in_stage("measure", "the polygon holds more than " + std::to_string(kMaxAreaPoints) +
                                             " points: measure a smaller area, or export its points (clip)");
    }
    std::vector<recon::Point3> ring;
    for (const auto& p : polygon) ring.push_back({p.x, p.y, p.z});
    recon::AreaVolumeOptions options;
    options.points_inside = true;  // chosen by clip's point test, in the dataset CRS's units
    return recon::measure_area_volume(ring, points, options);
}

std::string area_line(const dataset::Dataset& ds, std::span<const PickedPoint> polygon, const PointFilter& filter,
                      ThreadPool& pool, const pipelines::ReadWatch& watch) {
    try {
        return "area: " + recon::area_volume_summary(measure_area(ds, polygon, filter, pool, watch));
    } catch (const Error& e) {
        return std::string("area: ") + e.what();
    }
}

}  // namespace lidarscout::viewer
