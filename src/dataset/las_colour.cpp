// LAS colour to 8 bits: one channel's high byte for 16-bit colour, the value itself for 8-bit.
#include "dataset/las_colour.hpp"

namespace lidarscout::dataset {

Rgb8 rgb8_from_las(std::uint16_t r, std::uint16_t g, std::uint16_t b) {
    return rgb8_from_las(r, g, b, r > 255 || g > 255 || b > 255);
}

Rgb8 rgb8_from_las(std::uint16_t r, std::uint16_t g, std::uint16_t b, bool sixteen_bit) {
    const auto to8 = [sixteen_bit](std::uint16_t c) {
        return static_cast<std::uint8_t>(sixteen_bit ? c >> 8 : c);
    };
    return {to8(r), to8(g), to8(b)};
}

}  // namespace lidarscout::dataset
