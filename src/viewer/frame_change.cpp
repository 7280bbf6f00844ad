// FrameChange: a frame presented only when it changes what the window shows (see frame_change.hpp).
#include "viewer/frame_change.hpp"

#include <algorithm>
#include <cstring>

namespace lidarscout::viewer {

bool FrameChange::present(const render::RgbaImage& image, std::uint64_t panels, int width, int height,
                          std::chrono::steady_clock::time_point now, bool interacting) {
    const auto since = presented_at_ ? now - *presented_at_ : refresh_;
    const bool panels_wait = panels == panels_ || (!interacting && since < panels_interval_);
    const bool same = since < refresh_ && panels_wait && width == width_ && height == height_ &&
                      image.width == image_width_ && image.height == image_height_ &&
                      image.pixels.size() == pixels_.size() &&
                      std::equal(image.pixels.begin(), image.pixels.end(), pixels_.begin());
    if (same) return ++skipped_, false;
    pixels_.assign(image.pixels.begin(), image.pixels.end());
    image_width_ = image.width, image_height_ = image.height;
    width_ = width, height_ = height;
    panels_ = panels;
    presented_at_ = now;
    ++presented_;
    return true;
}

std::uint64_t fingerprint(const void* data, std::size_t n, std::uint64_t seed) {
    constexpr std::uint64_t kPrime = 0x100000001b3ull;
    const auto* bytes = static_cast<const unsigned char*>(data);
    std::uint64_t h = seed;
    std::size_t i = 0;
    for (; i + 8 <= n; i += 8) {
        std::uint64_t word = 0;
        std::memcpy(&word, bytes + i, 8);
        h = (h ^ word) * kPrime;
    }
    for (; i < n; ++i) h = (h ^ bytes[i]) * kPrime;
    return (h ^ n) * kPrime;
}

}  // namespace lidarscout::viewer
