// Picking: a batch at a time, the batch's screen rectangle first (from its bounds), then every
// point through the batch's float screen transform as the point pass draws it.
#include "viewer/picking.hpp"

#include <array>
#include <cmath>
#include <cstdio>
#include <numbers>

#include "las/classification.hpp"
#include "las/crs.hpp"
#include "viewer/visibility.hpp"

namespace lidarscout::viewer {
namespace {

// False when the box certainly projects farther than `radius` pixels from (px, py); true when
// it may not (its corners all in front of the camera and the rectangle near enough, or a
// corner behind the near plane, where the rectangle is unbounded).
bool box_may_cover(const render::Camera& camera, const dataset::Bounds& box, double px, double py, double radius) {
    if (!box_in_view(camera, box)) return false;
    double x0 = INFINITY, y0 = INFINITY, x1 = -INFINITY, y1 = -INFINITY;
    for (int corner = 0; corner < 8; ++corner) {
        const auto p = camera.project(corner & 1 ? box.max_x : box.min_x, corner & 2 ? box.max_y : box.min_y,
                                      corner & 4 ? box.max_z : box.min_z);
        if (!p) return true;
        x0 = std::min<double>(x0, p->x), x1 = std::max<double>(x1, p->x);
        y0 = std::min<double>(y0, p->y), y1 = std::max<double>(y1, p->y);
    }
    return px >= x0 - radius && px <= x1 + radius && py >= y0 - radius && py <= y1 + radius;
}

// Keeps in `best` the front-most point of `batch` within the radius (ties: the nearer pixel).
void pick_in_batch(const render::PointBatch& batch, const render::Camera& camera, double px, double py,
                   const PickOptions& options, std::optional<PickedPoint>& best, std::optional<std::uint32_t> tile,
                   bool chunk) {
    const auto t = camera.screen_transform(batch.origin_x, batch.origin_y, batch.origin_z);
    const double r2 = options.radius_px * options.radius_px;
    const PointFilter& filter = options.filter;
    for (const auto& a : batch.points) {
        if (!filter.keeps_drawn(a.classification, a.returns, a.intensity)) continue;
        const float w = t.depth[0] * a.dx + t.depth[1] * a.dy + t.depth[2] * a.dz + t.depth[3];
        if (!(w >= camera.near_m && w <= camera.far_m)) continue;
        const double sx = (t.sx[0] * a.dx + t.sx[1] * a.dy + t.sx[2] * a.dz + t.sx[3]) / w;
        const double sy = (t.sy[0] * a.dx + t.sy[1] * a.dy + t.sy[2] * a.dz + t.sy[3]) / w;
        const double d2 = (sx - px) * (sx - px) + (sy - py) * (sy - py);
        if (d2 > r2) continue;
        if (best && (w > best->depth || (w == best->depth && std::sqrt(d2) >= best->pixel_distance))) continue;
        PickedPoint p;
        p.x = batch.origin_x + a.dx, p.y = batch.origin_y + a.dy, p.z = batch.origin_z + a.dz;
        p.r = a.r, p.g = a.g, p.b = a.b;
        p.classification = a.classification, p.intensity = a.intensity;
        p.tile = tile, p.chunk_point = chunk;
        p.pixel_distance = std::sqrt(d2), p.depth = w;
        best = p;
    }
}

// The bounds of a point set (its points' extent), for the screen rectangle test.
dataset::Bounds set_bounds(const PointSet& set) {
    dataset::Bounds b;
    for (const auto& a : set.points) {
        const double x = set.origin_x + a.dx, y = set.origin_y + a.dy, z = set.origin_z + a.dz;
        b.extend({x, y, z, x, y, z});
    }
    return b;
}

}  // namespace

std::optional<PickedPoint> pick_point(const SceneSnapshot& snapshot, const render::Camera& camera, double px,
                                      double py, const PickOptions& options) {
    std::optional<PickedPoint> best;
    for (const auto& block : snapshot.full_points) {
        if (!box_may_cover(camera, block->bounds, px, py, options.radius_px)) continue;
        const auto batch = block->prefix(level_for(*block, camera, options.lod_spacing_px));
        pick_in_batch(batch, camera, px, py, options, best, block->tile, false);
    }
    if (!options.chunk_points) return best;
    for (const auto& set : snapshot.chunk_points) {
        if (set->points.empty() || !box_may_cover(camera, set_bounds(*set), px, py, options.radius_px)) continue;
        pick_in_batch(set->batch(), camera, px, py, options, best, std::nullopt, true);
    }
    return best;
}

std::optional<std::uint32_t> tile_at(const dataset::Dataset& dataset, double x, double y) {
    for (std::uint32_t i = 0; i < dataset.tiles.size(); ++i) {
        if (dataset.bounds(i).distance_xy(x, y) == 0) return i;
    }
    return std::nullopt;
}

PointReadout point_readout(const dataset::Dataset& dataset, const PickedPoint& point) {
    PointReadout r{point.x, point.y, point.z};
    const auto tile = point.tile ? point.tile : tile_at(dataset, point.x, point.y);
    if (!tile || *tile >= dataset.tiles.size() || !dataset.is_ready(*tile)) return r;  // (a header not read yet)
    const auto& t = dataset.tiles[*tile];
    r.file = t.tile.path();
    r.z = point.z / t.placed_z_to_metres();  // the file's vertical unit unless heights were transformed too
    if (t.to_frame) {  // reprojected into the dataset's CRS: x and y are in that CRS's units
        const auto unit = [](double to_metres) {
            return to_metres == 1 ? std::string("metre") : std::to_string(to_metres) + " m";
        };
        r.x = point.x / dataset.frame.xy_to_metres, r.y = point.y / dataset.frame.xy_to_metres;
        r.horizontal_unit = unit(dataset.frame.xy_to_metres);
        r.vertical_unit = t.heights_to_frame                      ? unit(dataset.frame.z_to_metres)
                          : t.tile.crs().vertical_unit_name.empty() ? las::unit_name(t.tile.crs().vertical_unit)
                                                                  : t.tile.crs().vertical_unit_name;
        r.crs = dataset.frame.crs + " (reprojected)";
        return r;
    }
    r.x = point.x / t.xy_to_metres, r.y = point.y / t.xy_to_metres;
    const auto& crs = t.tile.crs();
    r.horizontal_unit = crs.horizontal_unit_name.empty() ? las::unit_name(crs.horizontal_unit)
                                                         : crs.horizontal_unit_name;
    r.vertical_unit = crs.vertical_unit_name.empty() ? r.horizontal_unit : crs.vertical_unit_name;
    if (crs.epsg) r.crs = "EPSG:" + std::to_string(*crs.epsg);
    else r.crs = crs.name;
    return r;
}

std::string point_summary(const dataset::Dataset& dataset, const PickedPoint& point) {
    const PointReadout r = point_readout(dataset, point);
    char text[256];
    std::snprintf(text, sizeof text, "x %.3f y %.3f z %.3f (%s, z in %s%s%s)", r.x, r.y, r.z,
                  r.horizontal_unit.c_str(), r.vertical_unit.c_str(), r.crs.empty() ? "" : ", ", r.crs.c_str());
    std::string line = text;
    if (point.surface) {
        std::snprintf(text, sizeof text, " heightmap surface (interpolated, not a measured point) rgb %u %u %u",
                      point.r, point.g, point.b);
    } else {
        std::snprintf(text, sizeof text, " class %u (%s) intensity %u rgb %u %u %u", point.classification,
                      las::class_name(point.classification).c_str(), point.intensity, point.r, point.g, point.b);
    }
    line += text;
    if (point.lonlat) {
        char ll[64];
        std::snprintf(ll, sizeof ll, " lon %.7f lat %.7f", (*point.lonlat)[0], (*point.lonlat)[1]);
        line += ll;
    }
    if (point.chunk_point) line += " chunk point";
    if (!r.file.empty()) line += " " + r.file;
    return line;
}

std::string measurement_summary(const Measurement& m) {
    char text[160];
    std::snprintf(text, sizeof text, "distance %.3f m, horizontal %.3f m, height difference %+.3f m, slope %.1f deg",
                  m.distance_m, m.horizontal_m, m.dz_m, m.slope_deg);
    return text;
}

Measurement measure(const PickedPoint& a, const PickedPoint& b) {
    Measurement m;
    const double dx = b.x - a.x, dy = b.y - a.y;
    m.dz_m = b.z - a.z;
    m.horizontal_m = std::hypot(dx, dy);
    m.distance_m = std::hypot(m.horizontal_m, m.dz_m);
    m.slope_deg = m.distance_m > 0 ? std::atan2(m.dz_m, m.horizontal_m) * 180 / std::numbers::pi : 0;
    return m;
}

void ClickState::clicked(const std::optional<PickedPoint>& point) {
    missed = !point;
    if (!point) return;
    if (tool == ClickTool::Inspect) {
        picked = point;
    } else if (tool == ClickTool::Area) {
        if (area) polygon.clear(), area.reset();
        polygon.push_back(*point);
    } else if (!from || to) {
        from = point;
        to.reset();
    } else {
        to = point;
    }
}

void ClickState::use(ClickTool next) {
    if (next == tool) return;
    *this = ClickState{};
    tool = next;
}

}  // namespace lidarscout::viewer
