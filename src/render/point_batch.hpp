// The point data the point pass draws: batches of points stored as float offsets from a
// per-batch origin in double (world metres), so that float precision is spent on the few
// hundred metres a tile or chunk spans rather than on its ~1e6 m position.
#pragma once

#include <atomic>
#include <cstdint>
#include <span>

namespace lidarscout::render {

struct PointAttr {
    float dx = 0, dy = 0, dz = 0;  // metres from the batch origin
    std::uint8_t r = 0, g = 0, b = 0;
    std::uint8_t classification = 0;  // ASPRS class
    std::uint16_t intensity = 0;
};
static_assert(sizeof(PointAttr) == 20);

struct PointBatch {
    double origin_x = 0, origin_y = 0, origin_z = 0;  // world metres
    std::span<const PointAttr> points;
    // 0, or a key naming these exact points for as long as the key is used (from
    // new_point_cache_key, taken once the points no longer change): the CUDA backend then keeps
    // them on the GPU between frames instead of uploading them with every frame.
    std::uint64_t cache_key = 0;
};

// A key no other batch of this process has had.
inline std::uint64_t new_point_cache_key() {
    static std::atomic<std::uint64_t> next{1};
    return next.fetch_add(1, std::memory_order_relaxed);
}

}  // namespace lidarscout::render
