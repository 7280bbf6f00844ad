// Reading PNG files back in tests (stb_image, compiled once in png_test_util.cpp): pixels as
// render::pack_rgba values (red in the low byte), and the background colour of a resolve.
#pragma once

#include <cstdint>
#include <filesystem>
#include <vector>

#include "render/framebuffer.hpp"

namespace lidarscout::test {

struct Png {
    int width = 0, height = 0;
    std::vector<std::uint32_t> pixels;  // rgba8, red in the low byte
    bool ok() const { return width > 0; }
};

// An empty Png (ok() false) when the file cannot be read.
Png read_png(const std::filesystem::path& path);

inline const std::uint32_t kBackground = render::pack_rgba(24, 26, 32);  // render::ResolveSettings' default

// Pixels that are not the (opaque) background.
std::size_t drawn_pixels(const Png& png);

}  // namespace lidarscout::test
