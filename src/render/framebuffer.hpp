// The render target of every pass: one 64-bit word per pixel holding (depth << 32) | rgba,
// where depth is the positive view depth in metres as float bits (for positive floats the
// bit patterns order like the values) and rgba is 8 bits per channel, red in the low byte.
// A write is an atomic min, so any number of threads can draw into it in any order and the
// nearest fragment wins; an equal depth is settled by the colour bits, so the result does not
// depend on the order either. A cleared pixel holds kEmpty (all bits set), which is farther
// than any depth.
#pragma once

#include <atomic>
#include <bit>
#include <cstdint>
#include <vector>

namespace lidarscout::render {

inline constexpr std::uint64_t kEmpty = ~0ull;

inline std::uint32_t pack_rgba(std::uint8_t r, std::uint8_t g, std::uint8_t b, std::uint8_t a = 255) {
    return std::uint32_t{r} | std::uint32_t{g} << 8 | std::uint32_t{b} << 16 | std::uint32_t{a} << 24;
}
inline std::uint8_t red(std::uint32_t rgba) { return static_cast<std::uint8_t>(rgba); }
inline std::uint8_t green(std::uint32_t rgba) { return static_cast<std::uint8_t>(rgba >> 8); }
inline std::uint8_t blue(std::uint32_t rgba) { return static_cast<std::uint8_t>(rgba >> 16); }
inline std::uint8_t alpha(std::uint32_t rgba) { return static_cast<std::uint8_t>(rgba >> 24); }

// depth must be positive (the passes never write a depth below the camera's near plane).
inline std::uint64_t pack_fragment(float depth, std::uint32_t rgba) {
    return std::uint64_t{std::bit_cast<std::uint32_t>(depth)} << 32 | rgba;
}
inline float fragment_depth(std::uint64_t value) {
    return std::bit_cast<float>(static_cast<std::uint32_t>(value >> 32));
}
inline std::uint32_t fragment_rgba(std::uint64_t value) { return static_cast<std::uint32_t>(value); }

class Framebuffer {
public:
    // Throws lidarscout::Error unless both sizes are positive (and at most 32768).
    Framebuffer(int width, int height);
    // The constructor's check alone, without allocating.
    static void check_dimensions(int width, int height);

    int width() const { return width_; }
    int height() const { return height_; }
    // Throws lidarscout::Error naming `user` unless the framebuffer is width x height.
    void check_size(int width, int height, const char* user) const;

    void clear();
    // Atomic min of the fragment into pixel (x, y); the caller keeps x, y inside the image.
    void write(int x, int y, float depth, std::uint32_t rgba) { write_packed(x, y, pack_fragment(depth, rgba)); }
    void write_packed(int x, int y, std::uint64_t value) {
        std::atomic_ref<std::uint64_t> cell(pixels_[static_cast<std::size_t>(y) * width_ + x]);
        std::uint64_t old = cell.load(std::memory_order_relaxed);
        while (value < old && !cell.compare_exchange_weak(old, value, std::memory_order_relaxed)) {
        }
    }

    // Reads are for after drawing (no pass may be writing).
    std::uint64_t at(int x, int y) const { return pixels_[static_cast<std::size_t>(y) * width_ + x]; }
    bool empty_at(int x, int y) const { return at(x, y) == kEmpty; }
    const std::uint64_t* data() const { return pixels_.data(); }

private:
    int width_, height_;
    std::vector<std::uint64_t> pixels_;
};

}  // namespace lidarscout::render
