// Decoder of the BYTE14 item (extra bytes) of layered chunks (versions 3 and 4): one layer
// per byte, each coded as a difference to the byte's last value.
#pragma once

#include <vector>

#include "laz/point14/layer_common.hpp"

namespace lidarscout::laz::point14 {

// Adds one pass per extra byte (setup.layers has one stream per byte) if the caller wants
// the extra bytes.
void add_byte14_layers(const ItemSetup& setup, std::vector<PlacedLayer>& out);

}  // namespace lidarscout::laz::point14
