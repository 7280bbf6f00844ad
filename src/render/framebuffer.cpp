// Framebuffer allocation and clearing (the atomic write is inline in the header).
#include "render/framebuffer.hpp"

#include <algorithm>
#include <string>

#include "core/error.hpp"

namespace lidarscout::render {

static_assert(alignof(std::uint64_t) >= std::atomic_ref<std::uint64_t>::required_alignment);
static_assert(std::atomic_ref<std::uint64_t>::is_always_lock_free);

namespace {
constexpr int kMaxSide = 32768;
}

void Framebuffer::check_dimensions(int width, int height) {
    if (width <= 0 || height <= 0 || width > kMaxSide || height > kMaxSide) {
        throw Error("framebuffer size " + std::to_string(width) + "x" + std::to_string(height) +
                    " is not within 1.." + std::to_string(kMaxSide));
    }
}

Framebuffer::Framebuffer(int width, int height) : width_(width), height_(height) {
    check_dimensions(width, height);
    pixels_.assign(static_cast<std::size_t>(width) * height, kEmpty);
}

void Framebuffer::check_size(int width, int height, const char* user) const {
    if (width != width_ || height != height_) {
        throw Error(std::string(user) + ": the camera is " + std::to_string(width) + "x" + std::to_string(height) +
                    " but the framebuffer " + std::to_string(width_) + "x" + std::to_string(height_));
    }
}

void Framebuffer::clear() { std::fill(pixels_.begin(), pixels_.end(), kEmpty); }

}  // namespace lidarscout::render
