// The WAVEPACKET14 item of layered chunks (formats 9 and 10; versions 3 and 4; one layer): one file
// set (wavepacket14_v3.hpp/.cpp) holds this item version's decoder and encoder; the packet codec
// they run is shared with WAVEPACKET13 (items/wavepacket_codec.hpp). One set of models per scanner
// channel context (ChannelContexts, with the version 3 quirk).
#pragma once

#include <memory>
#include <vector>

#include "laz/items/point14/layer_common.hpp"
#include "laz/items/point14/layer_encoder.hpp"
#include "laz/items/wavepacket_codec.hpp"

namespace lidarscout::laz::detail::point14 {

inline constexpr std::size_t kWavepacket14Size = wavepacket::kSize;

// ---- Decoder
// Adds the item's layer pass if the caller wants wave packets.
void add_wavepacket14_layers(const ItemSetup& setup, std::vector<PlacedLayer>& out);

// ---- Encoder
// Adds the item's layer encoder (version 3): a layer that changes when a packet differs from the
// last one of its context, as LASzip's writer decides.
void add_wavepacket14_encoders(const ItemEncodeSetup& setup, std::vector<std::unique_ptr<LayerEncoder>>& out);

}  // namespace lidarscout::laz::detail::point14
