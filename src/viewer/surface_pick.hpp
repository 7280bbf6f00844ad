// Picking on the heightmaps: where the ray through a pixel first meets the surface the viewer
// draws for the patches that have no points yet (so a click on the overview gives a position
// and height before any full-resolution point arrives). The surface is taken as the bilinear
// interpolation between texel centres, extrapolated linearly in the outer half texels (the drawn
// mesh averages them at the texel corners and extrapolates on the boundary: the two differ by at
// most the terrain's curvature within a texel), and a texel without data is a hole the ray
// passes through.
#pragma once

#include <optional>

#include "render/camera.hpp"
#include "viewer/patch_heightmap.hpp"
#include "viewer/picking.hpp"
#include "viewer/scene_snapshot.hpp"

namespace lidarscout::viewer {

// The heightmap's height at (x, y) (world metres), or NaN outside it or in a texel without data.
float surface_height(const PatchHeightmap& heightmap, double x, double y);

// The first point of the snapshot's heightmaps along the ray through pixel (px, py), as a
// PickedPoint with `surface` set (colour of the texel hit; no class, intensity or tile);
// nullopt when the ray meets none in front of the camera.
std::optional<PickedPoint> pick_surface(const SceneSnapshot& snapshot, const render::Camera& camera, double px,
                                        double py);

// What a click picks: the front-most point within the radius unless the surface hides it (lies
// in front of it by more than 1% of its depth and 1 m), else the heightmap surface.
std::optional<PickedPoint> pick(const SceneSnapshot& snapshot, const render::Camera& camera, double px, double py,
                                const PickOptions& options = {});

}  // namespace lidarscout::viewer
