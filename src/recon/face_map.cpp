// The face map: each real triangle scanned row by row over its bounding box; per row the
// texels inside form one span, found from the three exact edge functions (see face_map.hpp).
#include "recon/face_map.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <utility>

#include "recon/grid_geometry.hpp"

namespace lidarscout::recon {
namespace {

constexpr double kUnit = static_cast<double>(kGridUnitsPerTexel);

std::int64_t floor_div(std::int64_t a, std::int64_t b) { return a / b - (a % b != 0 && a < 0); }

// Texel indices whose centres (i + 1/2) * unit lie in [lo, hi] (integer grid units), clipped to
// [inset, size - 1 - inset].
std::pair<int, int> texel_range(double lo, double hi, int size, int inset) {
    constexpr std::int64_t unit = kGridUnitsPerTexel, half = unit / 2;
    const std::int64_t first = -floor_div(half - static_cast<std::int64_t>(lo), unit);  // ceil((lo - half) / unit)
    const std::int64_t last = floor_div(static_cast<std::int64_t>(hi) - half, unit);
    return {static_cast<int>(std::max<std::int64_t>(first, inset)),
            static_cast<int>(std::min<std::int64_t>(last, size - 1 - inset))};
}

// One edge function e(p) = orient(from, to, p) on the texel centres: one texel right adds
// `step`, one row up adds `row_step`. All values are integers below 2^53: exact.
struct Edge {
    GridXY from, to;
    double step, row_step, inv_step;
    bool owns_ties;

    Edge(GridXY f, GridXY t)
        : from(f), to(t), step(-(t.y - f.y) * kUnit), row_step((t.x - f.x) * kUnit),
          inv_step(step != 0.0 ? 1.0 / step : 0.0), owns_ties(edge_owns_ties(f, t)) {}
    bool inside(double value, int k) const {
        const double e = value + step * k;
        return e > 0.0 || (e == 0.0 && owns_ties);
    }
};

// The columns k in [0, width) of a row where the edge is inside (e = value at k = 0): an
// interval, since e is monotone along the row. The root is estimated in floating point (to
// within a column or so), then settled by exact tests.
std::pair<int, int> edge_span(const Edge& edge, double value, int width) {
    if (edge.step == 0.0) return edge.inside(value, 0) ? std::pair{0, width - 1} : std::pair{0, -1};
    const int guess = static_cast<int>(std::clamp(-value * edge.inv_step, -1.0, static_cast<double>(width)));
    if (edge.step > 0.0) {  // outside ... outside inside ... inside: find the first inside
        int k = std::max(guess, 0);
        while (k > 0 && edge.inside(value, k - 1)) --k;
        while (k < width && !edge.inside(value, k)) ++k;
        return {k, width - 1};
    }
    int k = std::min(guess, width - 1);  // inside ... inside outside ...: find the last inside
    while (k < width - 1 && edge.inside(value, k + 1)) ++k;
    while (k >= 0 && !edge.inside(value, k)) --k;
    return {0, k};
}

void scan_triangle(const Triangulation& t, std::int32_t index, FaceMap& map, int inset) {
    const auto& tri = t.triangles[index];
    const GridXY a = t.vertices[tri[0]], b = t.vertices[tri[1]], c = t.vertices[tri[2]];
    const auto [col0, col1] = texel_range(std::min({a.x, b.x, c.x}), std::max({a.x, b.x, c.x}), map.size, inset);
    const auto [row0, row1] = texel_range(std::min({a.y, b.y, c.y}), std::max({a.y, b.y, c.y}), map.size, inset);
    if (col0 > col1 || row0 > row1) return;
    const int width = col1 - col0 + 1;
    const double inv_area = 1.0 / orient(a, b, c);
    const std::array<Edge, 3> edges{Edge(b, c), Edge(c, a), Edge(a, b)};  // opposite a, b, c
    const GridXY first{texel_centre(col0), texel_centre(row0)};
    std::array<double, 3> value{};  // edge functions at (col0, row)
    for (int k = 0; k < 3; ++k) value[k] = orient(edges[k].from, edges[k].to, first);
    for (int row = row0; row <= row1; ++row) {
        int lo = 0, hi = width - 1;
        for (int k = 0; k < 3 && lo <= hi; ++k) {
            const auto [from, to] = edge_span(edges[k], value[k], width);
            lo = std::max(lo, from);
            hi = std::min(hi, to);
        }
        std::size_t texel = static_cast<std::size_t>(row) * map.size + col0 + lo;
        for (int k = lo; k <= hi; ++k, ++texel) {
            map.face[texel] = index;
            map.bary[texel] = {static_cast<float>((value[0] + edges[0].step * k) * inv_area),
                               static_cast<float>((value[1] + edges[1].step * k) * inv_area),
                               static_cast<float>((value[2] + edges[2].step * k) * inv_area)};
        }
        for (int k = 0; k < 3; ++k) value[k] += edges[k].row_step;
    }
}

}  // namespace

FaceMap build_face_map(const Triangulation& triangulation, int size, int inset) {
    FaceMap map;
    map.size = size;
    const std::size_t texels = static_cast<std::size_t>(size) * size;
    map.face.assign(texels, -1);
    map.bary.assign(texels, {0.0f, 0.0f, 0.0f});
    for (std::size_t t = 0; t < triangulation.triangles.size(); ++t) {
        if (triangulation.is_real(t)) scan_triangle(triangulation, static_cast<std::int32_t>(t), map, inset);
    }
    return map;
}

}  // namespace lidarscout::recon
