// parse_bytes, parse_pixels (see size_options.hpp).
#include "cli/size_options.hpp"

#include <charconv>
#include <string_view>

#include "core/error.hpp"

namespace lidarscout::cli {
namespace {

double unit_factor(const std::string& unit) {
    if (unit.empty() || unit == "B") return 1.0;
    if (unit == "K") return 1024.0;
    if (unit == "M") return 1048576.0;
    if (unit == "G") return 1073741824.0;
    if (unit == "T") return 1099511627776.0;
    return -1.0;
}

int parse_int(std::string_view text) {
    int v = 0;
    const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), v);
    return ec == std::errc() && end == text.data() + text.size() ? v : -1;
}

}  // namespace

std::uint64_t parse_bytes(const std::string& text, const char* option) {
    double value = 0;
    const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), value);
    const double factor = unit_factor(std::string(end, text.data() + text.size()));
    if (ec != std::errc() || !(value > 0) || factor < 0 || !(value * factor < 1e19)) {
        throw Error("bad " + std::string(option) + " '" + text +
                    "': expected a size such as 512M, 4G or a number of bytes");
    }
    return static_cast<std::uint64_t>(value * factor);
}

std::pair<int, int> parse_pixels(const std::string& text, int min_pixels, const char* option) {
    const auto x = text.find('x');
    const int w = x == std::string::npos ? -1 : parse_int(std::string_view(text).substr(0, x));
    const int h = x == std::string::npos ? -1 : parse_int(std::string_view(text).substr(x + 1));
    if (w < min_pixels || h < min_pixels || w > 16384 || h > 16384) {
        throw Error("bad " + std::string(option) + " '" + text + "': expected WIDTHxHEIGHT in pixels (" +
                    std::to_string(min_pixels) + "..16384), e.g. 1280x720");
    }
    return {w, h};
}

}  // namespace lidarscout::cli
