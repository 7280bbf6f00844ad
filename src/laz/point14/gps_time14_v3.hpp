// The GPS time layer of POINT14 (item versions 3 and 4). Times are coded as the bit
// patterns of the doubles, in up to four interleaved sequences per scanner channel (e.g.
// pulses from several mirrors): each keeps its last time and a reference 32-bit delta. A
// symbol says whether the next time is that delta times a small multiple (plus a coded
// correction), a switch to another sequence, or a new sequence whose time is coded in full.
#pragma once

#include <span>

#include "laz/point14/layer_common.hpp"

namespace lidarscout::laz::point14 {

// The GPS time layer's pass (constant if the layer is empty in the chunk).
PlacedLayer make_gps_time14_layer(std::span<const std::uint8_t> stream, const ItemSetup& setup);

}  // namespace lidarscout::laz::point14
