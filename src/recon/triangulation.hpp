// Delaunay triangulation of a window's chunk points plus the corner padding points of
// Algorithm 1 (the paper): one point at each corner of the window (grid positions (0, 0),
// (E, 0), (E, E), (0, E) with E = grid_extent), so that the triangles cover the whole window.
// Padding points carry no values (the paper gives them NaN): a triangle with a padding vertex
// is "outside" and its texels fall back to the nearest chunk point. A corner that coincides
// with a chunk point gets no padding point. The padding changes the triangulation near the
// hull (the Delaunay triangles whose circumcircle holds a corner are replaced by padding
// triangles), exactly as in the paper; the texels of the real triangles are "inside the hull".
//
// Computed with CGAL (Delaunay_triangulation_2, exact predicates) on the exact grid positions;
// CGAL is confined to triangulation.cpp. Output is plain arrays.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include "recon/patch_space.hpp"

namespace lidarscout::recon {

struct Triangulation {
    std::vector<GridXY> vertices;  // the chunk points in their order, then the padding points
    std::size_t real_count = 0;    // vertices [0, real_count) are chunk points
    // Counter-clockwise vertex indices of each triangle.
    std::vector<std::array<std::int32_t, 3>> triangles;
    // neighbours[t][k]: the triangle across the edge opposite vertex k of t, -1 on the border.
    std::vector<std::array<std::int32_t, 3>> neighbours;

    bool is_padding_vertex(std::int32_t v) const { return static_cast<std::size_t>(v) >= real_count; }
    // A triangle whose three vertices are chunk points (one that interpolates).
    bool is_real(std::size_t t) const {
        const auto& tri = triangles[t];
        return !is_padding_vertex(tri[0]) && !is_padding_vertex(tri[1]) && !is_padding_vertex(tri[2]);
    }
};

// Triangulates `points` (distinct positions inside [0, extent]^2) with the padding corners, or,
// with `pad_corners` false, alone (the plain Delaunay triangulation, as a TIN of a DEM wants).
// Throws lidarscout::Error for a position outside the window or a repeated position.
Triangulation triangulate(std::span<const GridXY> points, std::int64_t extent, bool pad_corners = true);
// The same for a patch's points.
Triangulation triangulate(const PatchPoints& patch);

}  // namespace lidarscout::recon
