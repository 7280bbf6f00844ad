// measure_area_volume: the polygon's area, the points inside gridded, the base, cut and fill.
#include "recon/area_volume.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <vector>

#include "core/error.hpp"
#include "core/polygon.hpp"
#include "recon/texel_stats.hpp"

namespace lidarscout::recon {
namespace {

// z = a + b x + c y through the vertices (least squares, centred for precision).
std::array<double, 3> vertex_plane(std::span<const Point3> ring) {
    double cx = 0, cy = 0, cz = 0;
    for (const auto& p : ring) cx += p[0], cy += p[1], cz += p[2];
    const double n = static_cast<double>(ring.size());
    cx /= n, cy /= n, cz /= n;
    double sxx = 0, sxy = 0, syy = 0, sxz = 0, syz = 0;
    for (const auto& p : ring) {
        const double x = p[0] - cx, y = p[1] - cy, z = p[2] - cz;
        sxx += x * x, sxy += x * y, syy += y * y, sxz += x * z, syz += y * z;
    }
    const double det = sxx * syy - sxy * sxy;
    if (!(std::abs(det) > 1e-9 * std::max(1.0, sxx * syy))) {
        throw Error::in_stage("measure", "the polygon's vertices lie on one line: no base plane through them");
    }
    const double b = (sxz * syy - syz * sxy) / det, c = (syz * sxx - sxz * sxy) / det;
    return {cz - b * cx - c * cy, b, c};
}

struct Grid {
    double x0 = 0, y0 = 0, cell = 1;
    int nx = 0, ny = 0;
    std::vector<TexelStats> stats;
    std::vector<char> in;      // the cell's centre lies inside the polygon
    std::vector<float> height;  // NaN: no point (yet)

    double cx(int i) const { return x0 + (i + 0.5) * cell; }
    double cy(int j) const { return y0 + (j + 0.5) * cell; }
    std::size_t at(int i, int j) const { return static_cast<std::size_t>(j) * nx + i; }
};

// The polygon's outline as a MultiPolygon (the point-in-polygon test and area of clip's).
MultiPolygon outline(std::span<const Point3> ring) {
    Ring xy;
    for (const auto& p : ring) xy.push_back({p[0], p[1]});
    return MultiPolygon({{xy}});
}

constexpr double kMaxCells = 4e6;  // 128 MB of texel statistics

Grid make_grid(std::span<const Point3> ring, const MultiPolygon& shape, double cell) {
    double x0 = ring[0][0], x1 = x0, y0 = ring[0][1], y1 = y0;
    for (const auto& p : ring) x0 = std::min(x0, p[0]), x1 = std::max(x1, p[0]), y0 = std::min(y0, p[1]),
                               y1 = std::max(y1, p[1]);
    Grid g;
    g.cell = cell, g.x0 = x0, g.y0 = y0;
    const double cells = std::ceil((x1 - x0) / cell) * std::ceil((y1 - y0) / cell);
    if (!(cells <= kMaxCells)) {
        throw Error::in_stage("measure", "the polygon spans " + std::to_string(static_cast<long long>(cells)) +
                                             " cells of " + std::to_string(cell) + " m: draw a smaller one");
    }
    g.nx = std::max(1, static_cast<int>(std::ceil((x1 - x0) / cell)));
    g.ny = std::max(1, static_cast<int>(std::ceil((y1 - y0) / cell)));
    g.stats.resize(static_cast<std::size_t>(g.nx) * g.ny);
    g.in.resize(g.stats.size());
    g.height.assign(g.stats.size(), std::numeric_limits<float>::quiet_NaN());
    for (int j = 0; j < g.ny; ++j)
        for (int i = 0; i < g.nx; ++i) g.in[g.at(i, j)] = shape.contains(g.cx(i), g.cy(j));
    return g;
}

// Cells inside without points: the mean of their measured neighbours, ring by ring, at most
// kFillRings rings from a measured cell (farther ones stay unmeasured: nothing to say there).
constexpr int kFillRings = 3;

void fill_gaps(Grid& g, AreaVolume& out) {
    for (int ring = 0, changed = 1; changed && ring < kFillRings; ++ring) {
        changed = 0;
        std::vector<float> next = g.height;
        for (int j = 0; j < g.ny; ++j) {
            for (int i = 0; i < g.nx; ++i) {
                if (!g.in[g.at(i, j)] || !std::isnan(g.height[g.at(i, j)])) continue;
                double sum = 0;
                int n = 0;
                for (int dj = -1; dj <= 1; ++dj)
                    for (int di = -1; di <= 1; ++di) {
                        const int a = i + di, b = j + dj;
                        if (a < 0 || b < 0 || a >= g.nx || b >= g.ny) continue;
                        const float h = g.height[g.at(a, b)];
                        if (!std::isnan(h)) sum += h, ++n;
                    }
                if (n == 0) continue;
                next[g.at(i, j)] = static_cast<float>(sum / n);
                ++out.cells_filled;
                changed = 1;
            }
        }
        g.height.swap(next);
    }
}

// The surface's slope at a cell from its neighbours (central differences, one-sided at an edge).
double slope_factor(const Grid& g, int i, int j) {
    const auto h = [&](int a, int b) -> double {
        if (a < 0 || b < 0 || a >= g.nx || b >= g.ny) return NAN;
        return g.height[g.at(a, b)];
    };
    const auto derivative = [&](double minus, double here, double plus) {
        if (!std::isnan(minus) && !std::isnan(plus)) return (plus - minus) / (2 * g.cell);
        if (!std::isnan(plus)) return (plus - here) / g.cell;
        if (!std::isnan(minus)) return (here - minus) / g.cell;
        return 0.0;
    };
    const double here = h(i, j);
    const double zx = derivative(h(i - 1, j), here, h(i + 1, j)), zy = derivative(h(i, j - 1), here, h(i, j + 1));
    return std::sqrt(1 + zx * zx + zy * zy);
}

// The points inside the polygon (one point-in-polygon test each).
std::vector<Point3> points_inside(const MultiPolygon& shape, std::span<const Point3> points) {
    std::vector<Point3> out;
    for (const auto& p : points) {
        if (shape.contains(p[0], p[1])) out.push_back(p);
    }
    return out;
}

}  // namespace

AreaVolume measure_area_volume(std::span<const Point3> polygon, std::span<const Point3> points,
                               const AreaVolumeOptions& options) {
    if (polygon.size() < 3) throw Error::in_stage("measure", "an area needs at least 3 vertices");
    AreaVolume out;
    const MultiPolygon shape = outline(polygon);
    out.horizontal_area_m2 = shape.area();
    if (!(out.horizontal_area_m2 > 0)) throw Error::in_stage("measure", "the polygon has no area");
    out.base_plane = options.base_height ? std::array<double, 3>{*options.base_height, 0, 0} : vertex_plane(polygon);
    char base[64];
    if (options.base_height) std::snprintf(base, sizeof base, "height %.2f m", *options.base_height);
    else std::snprintf(base, sizeof base, "plane through the %zu vertices", polygon.size());
    out.base = base;
    std::vector<Point3> tested;  // (points chosen by the caller are used where they are)
    if (!options.points_inside) tested = points_inside(shape, points);
    const std::span<const Point3> inside = options.points_inside ? points : std::span<const Point3>(tested);
    if (inside.empty()) throw Error::in_stage("measure", "no point lies inside the polygon");
    out.points = inside.size();
    const double spacing = std::sqrt(out.horizontal_area_m2 / static_cast<double>(out.points));
    out.cell_m = options.cell_m > 0 ? options.cell_m : std::max(0.01, 2 * spacing);
    if (options.cell_m <= 0) {  // a polygon too large for cells that fine: coarser cells, not a refusal
        const double box = (shape.max_x() - shape.min_x()) * (shape.max_y() - shape.min_y());
        out.cell_m = std::max(out.cell_m, std::sqrt(box / kMaxCells) * 1.01);
    }
    Grid g = make_grid(polygon, shape, out.cell_m);
    for (const auto& p : inside) {  // on the polygon's edges a point may fall just past the first or last cell
        const double fi = std::clamp(std::floor((p[0] - g.x0) / g.cell), 0.0, g.nx - 1.0);
        const double fj = std::clamp(std::floor((p[1] - g.y0) / g.cell), 0.0, g.ny - 1.0);
        g.stats[g.at(static_cast<int>(fi), static_cast<int>(fj))].add(p[2], {});
    }
    for (std::size_t k = 0; k < g.stats.size(); ++k) g.height[k] = g.stats[k].height(TexelStatistic::Mean);
    fill_gaps(g, out);
    const double cell_area = g.cell * g.cell;
    for (int j = 0; j < g.ny; ++j) {
        for (int i = 0; i < g.nx; ++i) {
            if (!g.in[g.at(i, j)]) continue;
            ++out.cells;
            const float z = g.height[g.at(i, j)];
            if (std::isnan(z)) {
                ++out.cells_unmeasured;
                continue;
            }
            const double dz = z - (out.base_plane[0] + out.base_plane[1] * g.cx(i) + out.base_plane[2] * g.cy(j));
            (dz > 0 ? out.cut_m3 : out.fill_m3) += std::abs(dz) * cell_area;
            out.surface_area_m2 += cell_area * slope_factor(g, i, j);
        }
    }
    return out;
}

std::string area_volume_summary(const AreaVolume& a) {
    char text[384];
    std::snprintf(text, sizeof text,
                  "area %.1f m2 (surface %.1f m2), cut %.1f m3, fill %.1f m3 over the %s; %llu points in %llu "
                  "cells of %.2f m (%llu filled from neighbours, %llu unmeasured)",
                  a.horizontal_area_m2, a.surface_area_m2, a.cut_m3, a.fill_m3, a.base.c_str(),
                  static_cast<unsigned long long>(a.points), static_cast<unsigned long long>(a.cells), a.cell_m,
                  static_cast<unsigned long long>(a.cells_filled), static_cast<unsigned long long>(a.cells_unmeasured));
    return text;
}

}  // namespace lidarscout::recon
