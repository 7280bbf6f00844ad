// Decoder of the RGBNIR14 item of layered chunks (versions 3 and 4): two layers, the colour
// (coded like RGB14) and the near-infrared value, whose two bytes are each either repeated
// or corrected from their last value.
#pragma once

#include <vector>

#include "laz/point14/layer_common.hpp"

namespace lidarscout::laz::point14 {

inline constexpr std::size_t kRgbNir14Size = 8;

// Adds the passes of the layers the caller wants (colour, NIR).
void add_rgbnir14_layers(const ItemSetup& setup, std::vector<PlacedLayer>& out);

}  // namespace lidarscout::laz::point14
