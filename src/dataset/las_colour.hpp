// LAS colour to the 8 bits per channel the overview and the viewer keep: a file's colour depth
// decided once from a sample of its points, then each point's channels scaled by it.
#pragma once

#include <cstdint>

#include "core/patch_grid.hpp"

namespace lidarscout::dataset {

// LAS colour (16-bit channels) to 8 bits: the high byte when any channel exceeds 255 (a
// true 16-bit colour), else the values as they are (files that store 8-bit colour).
Rgb8 rgb8_from_las(std::uint16_t r, std::uint16_t g, std::uint16_t b);
// The same with the depth decided once for a whole file (see colour_is_16bit), so that a
// dark point of a 16-bit file is not mistaken for an 8-bit one.
Rgb8 rgb8_from_las(std::uint16_t r, std::uint16_t g, std::uint16_t b, bool sixteen_bit);
// A file's colour depth from a sample of its points (e.g. its chunk points): 16-bit when
// any channel of any sample exceeds 255. `max_channel(sample)` gives its largest channel.
template <typename Range, typename MaxChannel>
bool colour_is_16bit(const Range& samples, MaxChannel max_channel) {
    for (const auto& s : samples) {
        if (max_channel(s) > 255) return true;
    }
    return false;
}

}  // namespace lidarscout::dataset
