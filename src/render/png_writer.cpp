// PNG output through stb_image_write, compiled here (its functions kept static to this file,
// so no other user of stb in the program can clash with it).
#include "render/png_writer.hpp"

#include <bit>
#include <optional>

#include "core/error.hpp"

#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wmissing-field-initializers"
#pragma GCC diagnostic ignored "-Wunused-function"
#pragma GCC diagnostic ignored "-Wsign-compare"
#define STB_IMAGE_WRITE_STATIC
#define STB_IMAGE_WRITE_IMPLEMENTATION
#include <stb/stb_image_write.h>
#pragma GCC diagnostic pop

namespace lidarscout::render {

void write_png(const std::string& path, const RgbaImage& image) {
    if (image.width <= 0 || image.height <= 0 ||
        image.pixels.size() != static_cast<std::size_t>(image.width) * image.height) {
        throw Error(path, std::nullopt, "cannot write PNG: the image is empty or inconsistent");
    }
    // rgba8 words with red in the low byte are R, G, B, A bytes in memory on little-endian.
    static_assert(std::endian::native == std::endian::little);
    const int ok = stbi_write_png(path.c_str(), image.width, image.height, 4, image.pixels.data(), image.width * 4);
    if (!ok) throw Error(path, std::nullopt, "cannot write PNG");
}

}  // namespace lidarscout::render
