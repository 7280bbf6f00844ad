// Decoder of the WAVEPACKET14 item of layered chunks (formats 9 and 10; versions 3 and 4;
// one layer): descriptor index, offset of the waveform data (same as last, right after the
// last packet, a coded delta, or raw), packet size, return point location and the XYZ(t)
// direction, each predicted from the last point's value.
#pragma once

#include <vector>

#include "laz/items/point14/layer_common.hpp"

namespace lidarscout::laz::detail::point14 {

inline constexpr std::size_t kWavepacket14Size = 29;

// Adds the item's layer pass if the caller wants wave packets.
void add_wavepacket14_layers(const ItemSetup& setup, std::vector<PlacedLayer>& out);

}  // namespace lidarscout::laz::detail::point14
