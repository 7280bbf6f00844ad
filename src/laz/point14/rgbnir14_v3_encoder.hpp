// Encoder of the RGBNIR14 item, version 3 (the mirror of rgbnir14_v3.hpp): the colour layer
// (as RGB14) and the NIR layer.
#pragma once

#include <memory>
#include <vector>

#include "laz/point14/layer_encoder.hpp"

namespace lidarscout::laz::point14 {

// Adds the item's two layer encoders (colour, NIR).
void add_rgbnir14_encoders(const ItemEncodeSetup& setup, std::vector<std::unique_ptr<LayerEncoder>>& out);

}  // namespace lidarscout::laz::point14
