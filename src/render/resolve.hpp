// The resolve pass: turns the framebuffer's (depth, colour) words into an RGBA8 image, with
// the background colour where nothing was drawn and optional eye-dome lighting (EDL), which
// darkens a pixel by how much farther it is than its neighbours (in log depth), outlining
// depth edges without needing normals.
#pragma once

#include <cstdint>
#include <vector>

#include "core/thread_pool.hpp"
#include "render/framebuffer.hpp"

namespace lidarscout::render {

struct RgbaImage {
    int width = 0, height = 0;
    std::vector<std::uint32_t> pixels;  // row-major, row 0 at the top, rgba8 (red in the low byte)

    std::uint32_t at(int x, int y) const { return pixels[static_cast<std::size_t>(y) * width + x]; }
};

struct ResolveSettings {
    std::uint32_t background = pack_rgba(24, 26, 32);
    float edl_strength = 0.0f;  // 0 = off; 1 = a pixel 1% farther than all 4 neighbours gets ~0.5x
    int edl_radius_px = 1;      // distance to the 4 neighbours compared
};

// EDL response of one pixel: mean over the 4 neighbours at `radius` of
// max(0, log2(depth) - log2(neighbour depth)); empty neighbours and the image border count 0.
// The brightness factor is exp(-kEdlScale * strength * response).
inline constexpr float kEdlScale = 100.0f;

RgbaImage resolve(const Framebuffer& fb, const ResolveSettings& settings, ThreadPool& pool);

}  // namespace lidarscout::render
