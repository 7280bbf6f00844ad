// Algorithm 1 of the paper: from a window's chunk points to the four 96 x 96 images the
// network takes: nearest-neighbour and linear height, nearest-neighbour and linear colour.
// Linear = barycentric interpolation inside the real triangles (face map), the nearest chunk
// point outside them. Also the shared pieces the other methods reuse: the patch geometry
// (triangulation, face map, nearest map) and the nearest / linear image fills.
#pragma once

#include <cstdint>
#include <vector>

#include "recon/face_map.hpp"
#include "recon/patch_space.hpp"
#include "recon/triangulation.hpp"

namespace lidarscout::recon {

// Everything about a window's points that does not depend on the values interpolated.
struct PatchGeometry {
    Triangulation triangulation;
    FaceMap face_map;
    std::vector<std::int32_t> nearest;  // per texel: index of the nearest chunk point
};
PatchGeometry build_geometry(const PatchPoints& patch);

// Writes value(c, nearest[texel]) into every texel of every channel; with `outside_of`, only
// into the texels outside its real triangles. `image` must have values.channels channels.
void fill_nearest(Image& image, const std::vector<std::int32_t>& nearest, const PointValues& values,
                  const FaceMap* outside_of = nullptr);
// Writes the barycentric interpolation of the values into every texel inside a real triangle.
void fill_linear(Image& image, const Triangulation& triangulation, const FaceMap& map, const PointValues& values);

// Nearest everywhere / linear inside with nearest outside, for any per-point values.
Image nearest_image(const PatchGeometry& geometry, const PointValues& values);
Image linear_image(const PatchGeometry& geometry, const PointValues& values);

// The network's inputs (all empty when status is TooFewPoints).
struct InterpolatedPatch {
    PatchStatus status = PatchStatus::TooFewPoints;
    Image height_nearest, height_linear;  // 1 channel, normalised heights
    Image rgb_nearest, rgb_linear;        // 3 channels in [0, 1] (NaN without colour)
    FaceMap face_map;
    float mean_height = 0;  // mean normalised height of the window's chunk points (released model's centre)
};
InterpolatedPatch interpolate_patch(const PatchPoints& patch);

}  // namespace lidarscout::recon
