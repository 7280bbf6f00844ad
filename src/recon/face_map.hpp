// The face map of Algorithm 1: for every texel of the window, the real triangle (all three
// vertices chunk points) whose closed area holds the texel centre, or -1 when the centre lies
// in a padding triangle (outside the hull of the chunk points), with the texel's barycentric
// coordinates in that triangle.
//
// The paper fills it by flood fill from each triangle's centroid plus a second pass for the
// disconnected rests of slender triangles. Here each real triangle is scanned over the texels
// of its bounding box with exact orientation tests: the same set of texels per triangle (the
// centres inside it), with no missed texel for slivers and with one explicit tie rule
// (grid_geometry.hpp) for centres exactly on a shared edge or vertex, where the flood fill
// keeps whichever triangle came first.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "recon/triangulation.hpp"

namespace lidarscout::recon {

struct FaceMap {
    int size = 0;                              // texels per side
    std::vector<std::int32_t> face;            // [row * size + col]: triangle index or -1
    std::vector<std::array<float, 3>> bary;    // barycentrics of the texel centre (face >= 0)

    std::int32_t at(int row, int col) const { return face[static_cast<std::size_t>(row) * size + col]; }
};

// With `inset` > 0, only the texels at least `inset` texels from every edge of the window are
// mapped (the others stay -1): for callers that keep only the window's centre.
FaceMap build_face_map(const Triangulation& triangulation, int size, int inset = 0);

// Calls fn(texel, triangle, barycentrics) for every texel inside a real triangle, in texel order
// (texel = row * size + col).
template <typename Fn>
void for_each_inside_texel(const FaceMap& map, Fn&& fn) {
    for (std::size_t texel = 0; texel < map.face.size(); ++texel) {
        if (map.face[texel] >= 0) fn(texel, map.face[texel], map.bary[texel]);
    }
}

}  // namespace lidarscout::recon
