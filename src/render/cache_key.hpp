// Keys that name data the CUDA backend may keep in GPU memory from frame to frame (point
// batches, heightmap patches): a key is taken once its data no longer changes and always names
// that same data; 0 means "upload with every frame".
#pragma once

#include <atomic>
#include <cstdint>

namespace lidarscout::render {

// A key no other batch or patch of this process has had.
inline std::uint64_t new_cache_key() {
    static std::atomic<std::uint64_t> next{1};
    return next.fetch_add(1, std::memory_order_relaxed);
}

}  // namespace lidarscout::render
