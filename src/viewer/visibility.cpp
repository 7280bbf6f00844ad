// Frustum tests and screen coverage of boxes; visible patches; the full-resolution tile choice.
#include "viewer/visibility.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <numbers>
#include <utility>
#include <vector>

#include "viewer/point_sets.hpp"

namespace lidarscout::viewer {
namespace {

// A box corner in the camera's frame: lateral (right), vertical (up) and depth.
struct ViewPoint {
    double right = 0, up = 0, depth = 0;
};

std::array<ViewPoint, 8> view_corners(const render::Camera& camera, const dataset::Bounds& b) {
    const render::ViewBasis basis = camera.basis();
    std::array<ViewPoint, 8> out;
    for (int c = 0; c < 8; ++c) {
        const std::array<double, 3> v = {((c & 1) ? b.max_x : b.min_x) - camera.x,
                                         ((c & 2) ? b.max_y : b.min_y) - camera.y,
                                         ((c & 4) ? b.max_z : b.min_z) - camera.z};
        const auto dot = [&](const std::array<double, 3>& axis) {
            return v[0] * axis[0] + v[1] * axis[1] + v[2] * axis[2];
        };
        out[c] = {dot(basis.right), dot(basis.up), dot(basis.forward)};
    }
    return out;
}

// (kept per thread for its field of view, as the camera's basis is: asked for every box of a country)
double half_tan_v(const render::Camera& camera) {
    thread_local double made_fov = std::numeric_limits<double>::quiet_NaN(), made = 0;
    if (camera.fov_deg != made_fov) made = std::tan(0.5 * camera.fov_deg * std::numbers::pi / 180.0);
    made_fov = camera.fov_deg;
    return made;
}

}  // namespace

bool box_in_view(const render::Camera& camera, const dataset::Bounds& box) {
    if (box.empty()) return false;
    const double tv = half_tan_v(camera), th = tv * camera.width / std::max(1, camera.height);
    std::array<int, 6> outside{};
    for (const ViewPoint& p : view_corners(camera, box)) {
        outside[0] += p.right > p.depth * th;
        outside[1] += -p.right > p.depth * th;
        outside[2] += p.up > p.depth * tv;
        outside[3] += -p.up > p.depth * tv;
        outside[4] += p.depth < camera.near_m;
        outside[5] += p.depth > camera.far_m;
    }
    return std::none_of(outside.begin(), outside.end(), [](int n) { return n == 8; });
}

double screen_fraction(const render::Camera& camera, const dataset::Bounds& box) {
    if (!box_in_view(camera, box)) return 0.0;
    double x0 = camera.width, x1 = 0, y0 = camera.height, y1 = 0;
    for (int c = 0; c < 8; ++c) {
        const auto p = camera.project((c & 1) ? box.max_x : box.min_x, (c & 2) ? box.max_y : box.min_y,
                                      (c & 4) ? box.max_z : box.min_z);
        if (!p) return 1.0;  // reaches behind the near plane (or past the far plane) while in view
        x0 = std::min<double>(x0, p->x), x1 = std::max<double>(x1, p->x);
        y0 = std::min<double>(y0, p->y), y1 = std::max<double>(y1, p->y);
    }
    x0 = std::max(x0, 0.0), y0 = std::max(y0, 0.0);
    x1 = std::min<double>(x1, camera.width), y1 = std::min<double>(y1, camera.height);
    if (x1 <= x0 || y1 <= y0) return 0.0;
    return (x1 - x0) * (y1 - y0) / (static_cast<double>(camera.width) * camera.height);
}

double distance_to(const render::Camera& camera, const dataset::Bounds& box) {
    const auto gap = [](double lo, double hi, double p) { return std::max({lo - p, 0.0, p - hi}); };
    return std::hypot(gap(box.min_x, box.max_x, camera.x), gap(box.min_y, box.max_y, camera.y),
                      gap(box.min_z, box.max_z, camera.z));
}

dataset::Bounds cell_box(const lidarscout::PatchGrid& grid, lidarscout::CellKey cell, double z_min, double z_max) {
    dataset::Bounds b;
    b.min_x = grid.cell_min_x(cell), b.max_x = b.min_x + grid.patch_size();
    b.min_y = grid.cell_min_y(cell), b.max_y = b.min_y + grid.patch_size();
    b.min_z = z_min, b.max_z = z_max;
    return b;
}

std::vector<lidarscout::CellKey> visible_cells(const lidarscout::PatchGrid& grid, const render::Camera& camera,
                                            double z_min, double z_max) {
    std::vector<lidarscout::CellKey> out;
    for (const auto cell : grid.cells()) {
        if (box_in_view(camera, cell_box(grid, cell, z_min, z_max))) out.push_back(cell);
    }
    return out;
}

FullResChoice choose_full_res_tiles(const dataset::Dataset& dataset, const render::Camera& camera,
                                    const FullResOptions& options) {
    std::vector<std::uint32_t> visible, large;
    for (std::uint32_t i = 0; i < dataset.tiles.size(); ++i) {
        const double f = screen_fraction(camera, dataset.bounds(i));
        if (f <= 0.0) continue;
        visible.push_back(i);
        if (f > options.min_screen_fraction) large.push_back(i);
    }
    std::vector<std::uint32_t> wanted = visible.size() <= options.few_tiles ? visible : large;
    // (distances taken once: a tile's bounds change when its header is read, maybe while this sorts)
    std::vector<std::pair<double, std::uint32_t>> near;
    for (const std::uint32_t i : wanted) near.emplace_back(distance_to(camera, dataset.bounds(i)), i);
    std::stable_sort(near.begin(), near.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
    for (std::size_t k = 0; k < near.size(); ++k) wanted[k] = near[k].second;
    FullResChoice choice;
    choice.wanted = wanted.size();
    for (const std::uint32_t i : wanted) {
        const std::uint64_t bytes = tile_point_set_bytes(dataset.tiles[i]);
        if (choice.bytes + bytes > options.memory_budget) {
            ++choice.over_budget;
            continue;
        }
        choice.bytes += bytes;
        choice.tiles.push_back(i);
    }
    return choice;
}

}  // namespace lidarscout::viewer
