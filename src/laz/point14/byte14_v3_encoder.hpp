// Encoder of the BYTE14 item (extra bytes), version 3 (the mirror of byte14_v3.hpp): one
// layer per byte, each byte coded as its difference to the byte's last value.
#pragma once

#include <memory>
#include <vector>

#include "laz/point14/layer_encoder.hpp"

namespace lidarscout::laz::point14 {

// Adds one layer encoder per byte of an item of `size` bytes.
void add_byte14_encoders(const ItemEncodeSetup& setup, std::size_t size,
                         std::vector<std::unique_ptr<LayerEncoder>>& out);

}  // namespace lidarscout::laz::point14
