// Rasterizes one screen-space triangle into the framebuffer: edge functions over the bounding
// box with exact integer arithmetic on a 1/256-pixel grid and the top-left fill rule, so two
// triangles sharing an edge cover every pixel centre along it exactly once (no cracks, no
// double coverage). Depth is interpolated perspective-correctly (1/depth is affine on screen),
// colours linearly on screen (exact enough for the small triangles of a heightmap).
#pragma once

#include <cstdint>

#include "render/framebuffer.hpp"

namespace lidarscout::render {

struct RasterVertex {
    float x = 0, y = 0;        // pixel coordinates (pixel centres at i + 0.5)
    float depth = 0;           // view depth in metres, > 0
    float r = 0, g = 0, b = 0;  // colour, 0..255
};

// Vertices farther than this from the image origin (in pixels) are not drawn (the triangle is
// dropped), which keeps the fixed-point edge functions exact in 64-bit integers.
inline constexpr float kGuardBandPx = 1 << 20;

// Draws the triangle (either winding) with its colours multiplied by `shade` and its depth
// multiplied by `depth_scale` (> 1 pushes it back: the heightmap's depth bias). Degenerate
// triangles and triangles outside the guard band draw nothing.
void draw_triangle(Framebuffer& fb, const RasterVertex& a, const RasterVertex& b, const RasterVertex& c, float shade,
                   float depth_scale);

}  // namespace lidarscout::render
