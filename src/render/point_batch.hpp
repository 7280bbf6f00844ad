// The point data the point pass draws: batches of points stored as float offsets from a
// per-batch origin in double (world metres), so that float precision is spent on the few
// hundred metres a tile or chunk spans rather than on its ~1e6 m position.
#pragma once

#include <cstdint>
#include <span>

#include "render/cache_key.hpp"

namespace lidarscout::render {

struct PointAttr {
    float dx = 0, dy = 0, dz = 0;  // metres from the batch origin
    std::uint8_t r = 0, g = 0, b = 0;
    std::uint8_t classification = 0;  // ASPRS class
    std::uint16_t intensity = 0;
    std::uint8_t returns = 0;         // return kinds (core/point_filter.hpp returns::), 0 when unknown
};
static_assert(sizeof(PointAttr) == 20);

struct PointBatch {
    double origin_x = 0, origin_y = 0, origin_z = 0;  // world metres
    std::span<const PointAttr> points;
    std::uint64_t cache_key = 0;  // 0, or new_cache_key() (cache_key.hpp): kept on the GPU
    // The distance between neighbouring points on the ground (metres), 0 when unknown: where it
    // is more than a pixel on screen, an adaptive point pass draws each point as a square of
    // about that size, so that near points close up instead of leaving the surface between them.
    float spacing_m = 0;
};

}  // namespace lidarscout::render
