// Encoder of the GPS time layer of POINT14 (version 3), the mirror of gps_time14_v3.hpp: for
// every time that changed it picks the symbol LASzip's writer picks (a multiple of the
// sequence's reference delta plus a correction, a switch to another of the channel's four
// sequences, or a new sequence coded in full).
#pragma once

#include <memory>

#include "laz/point14/layer_encoder.hpp"

namespace lidarscout::laz::point14 {

std::unique_ptr<LayerEncoder> make_gps_time14_encoder(const ItemEncodeSetup& setup);

}  // namespace lidarscout::laz::point14
