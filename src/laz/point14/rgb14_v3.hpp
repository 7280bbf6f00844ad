// Decoder of the RGB14 item of layered chunks (versions 3 and 4; one layer), and the colour
// layer that RGBNIR14 shares. A 7-bit symbol says which of the six colour bytes changed and
// whether the colour is grey; red's bytes are coded against the last red, green's and
// blue's against their last value shifted by red's (and, for blue, green's) change.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "laz/point14/layer_common.hpp"

namespace lidarscout::laz::point14 {

inline constexpr std::size_t kRgb14Size = 6;

// The pass of a colour layer (16-bit R, G, B at the start of the item).
PlacedLayer make_rgb_layer(std::span<const std::uint8_t> stream, const ItemSetup& setup);

// Adds the RGB14 item's layer pass if the caller wants colour.
void add_rgb14_layers(const ItemSetup& setup, std::vector<PlacedLayer>& out);

}  // namespace lidarscout::laz::point14
