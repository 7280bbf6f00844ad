// PNG reading for tests (see png_test_util.hpp); the one place stb_image is compiled.
#include "png_test_util.hpp"

#include <algorithm>

#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wmissing-field-initializers"
#pragma GCC diagnostic ignored "-Wunused-function"
#pragma GCC diagnostic ignored "-Wsign-compare"
#define STB_IMAGE_STATIC
#define STB_IMAGE_IMPLEMENTATION
#include <stb/stb_image.h>
#pragma GCC diagnostic pop

namespace lidarscout::test {

Png read_png(const std::filesystem::path& path) {
    Png png;
    int channels = 0;
    unsigned char* data = stbi_load(path.string().c_str(), &png.width, &png.height, &channels, 4);
    if (!data) return {};
    png.pixels.resize(static_cast<std::size_t>(png.width) * png.height);
    for (std::size_t i = 0; i < png.pixels.size(); ++i) {
        png.pixels[i] = render::pack_rgba(data[4 * i], data[4 * i + 1], data[4 * i + 2], data[4 * i + 3]);
    }
    stbi_image_free(data);
    return png;
}

std::size_t drawn_pixels(const Png& png) {
    return static_cast<std::size_t>(std::count_if(png.pixels.begin(), png.pixels.end(), [](std::uint32_t p) {
        return (p & 0xffffffu) != (kBackground & 0xffffffu);
    }));
}

}  // namespace lidarscout::test
