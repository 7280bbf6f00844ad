// Encoders of the RGB14 item (one colour layer) and of the colour layer RGBNIR14 shares
// with it, version 3: the mirror of rgb14_v3.hpp.
#pragma once

#include <memory>
#include <vector>

#include "laz/point14/layer_encoder.hpp"

namespace lidarscout::laz::point14 {

// The encoder of a colour layer (16-bit R, G, B at the start of the item).
std::unique_ptr<LayerEncoder> make_rgb_encoder(const ItemEncodeSetup& setup);

// Adds the RGB14 item's layer encoder.
void add_rgb14_encoders(const ItemEncodeSetup& setup, std::vector<std::unique_ptr<LayerEncoder>>& out);

}  // namespace lidarscout::laz::point14
