// Parsing of size-like option values shared by `render` and `view`: memory sizes ("512M",
// "4G", "1.5G", a number of bytes) and image sizes ("1280x720").
#pragma once

#include <cstdint>
#include <string>
#include <utility>

namespace lidarscout::cli {

// A positive size in bytes; throws lidarscout::Error naming `option` otherwise.
std::uint64_t parse_bytes(const std::string& text, const char* option = "--memory");

// WIDTHxHEIGHT, each in [min_pixels, 16384]; throws lidarscout::Error naming `option`.
std::pair<int, int> parse_pixels(const std::string& text, int min_pixels, const char* option = "--size");

}  // namespace lidarscout::cli
