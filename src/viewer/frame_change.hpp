// Whether a frame changes what the window shows. The viewer draws its loop at up to 60 frames a second;
// most frames of a still view show exactly the picture and panels of the one before. Presenting those
// again (uploading the image, blitting it, drawing the panels, swapping) costs a software OpenGL such as
// Mesa's llvmpipe under Xvfb a core's fraction that a country's opening needs for its reads: 152,100
// tiles' chunk points took a third of both cores' time at 60 presents a second. A frame is presented
// when its image or the window's size differ from the last presented, when its panels (a fingerprint of
// their draw data) do and the user is at them (the mouse moving, a button or key down) or `panels` has
// passed since the last present (a panel's counters that change every frame while a dataset loads,
// read at 10 a second, not 60: those presents held a core), and at least every `refresh` whatever (a
// window uncovered, a compositor that lost it).
#pragma once

#include <chrono>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <vector>

#include "render/resolve.hpp"

namespace lidarscout::viewer {

class FrameChange {
public:
    explicit FrameChange(std::chrono::milliseconds refresh = std::chrono::milliseconds(500),
                         std::chrono::milliseconds panels = std::chrono::milliseconds(100))
        : refresh_(refresh), panels_interval_(panels) {}

    // True when this frame is to be presented (then it is taken as the last presented): `image` is the picture,
    // `panels` a fingerprint of everything drawn over it, `width` x `height` the window's framebuffer;
    // `interacting`: the user is at the panels this frame (a change of theirs is shown at once).
    bool present(const render::RgbaImage& image, std::uint64_t panels, int width, int height,
                 std::chrono::steady_clock::time_point now = std::chrono::steady_clock::now(),
                 bool interacting = true);

    std::uint64_t presented() const { return presented_; }  // frames presented
    std::uint64_t skipped() const { return skipped_; }      // frames that changed nothing

private:
    std::chrono::milliseconds refresh_, panels_interval_;
    std::vector<std::uint32_t> pixels_;  // of the image last presented
    int image_width_ = 0, image_height_ = 0, width_ = 0, height_ = 0;
    std::uint64_t panels_ = 0;
    std::optional<std::chrono::steady_clock::time_point> presented_at_;
    std::uint64_t presented_ = 0, skipped_ = 0;
};

// A 64-bit fingerprint of `n` bytes at `data`, continued from `seed` (FNV-1a over 8-byte words: for draw
// data of a few thousand vertices, not for adversaries).
std::uint64_t fingerprint(const void* data, std::size_t n, std::uint64_t seed = 0xcbf29ce484222325ull);

}  // namespace lidarscout::viewer
