// Writes a resolved image as a PNG file (stb_image_write, Debian libstb-dev).
#pragma once

#include <string>

#include "render/resolve.hpp"

namespace lidarscout::render {

// Writes `image` (RGBA8) to `path`; throws lidarscout::Error naming the path on failure.
void write_png(const std::string& path, const RgbaImage& image);

}  // namespace lidarscout::render
