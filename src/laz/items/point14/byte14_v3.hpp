// The BYTE14 item (extra bytes) of layered chunks, versions 3 and 4 (one layer per byte): one file
// set (byte14_v3.hpp/.cpp) holds all of this item version, nothing of it lives elsewhere: its
// symbols, the state its decoder and encoder share, the decoder and the encoder.
#pragma once

#include <cstddef>
#include <cstdint>
#include <memory>
#include <vector>

#include "laz/arithmetic_models.hpp"
#include "laz/items/point14/layer_common.hpp"
#include "laz/items/point14/layer_encoder.hpp"

namespace lidarscout::laz::detail::point14 {

// ---- State shared by the decoder and the encoder
// What the decoder and the encoder (byte14_v3.cpp) of a BYTE14
// layer (one extra byte) share, defined once: the value, how it is read from a raw item,
// and the model of a channel context.

// The codecs derive from this (see ContextLayer and ContextLayerEncoder).
struct Byte14State {
    using Value = std::uint8_t;
    struct Models {
        SymbolModel difference{256};
        void begin(Value&) {}
    };
    std::size_t offset = 0;  // the byte's position in the item

    Value read(const std::uint8_t* item) const { return item[offset]; }
};

// ---- Decoder
// Decoder of the BYTE14 item (extra bytes) of layered chunks (versions 3 and 4): one layer
// per byte, each coded as a difference to the byte's last value.

// Adds one pass per extra byte (setup.layers has one stream per byte) if the caller wants
// the extra bytes.
void add_byte14_layers(const ItemSetup& setup, std::vector<PlacedLayer>& out);

// ---- Encoder
// Encoder of the BYTE14 item (extra bytes), version 3 (the mirror of the decoder above): one
// layer per byte, each byte coded as its difference to the byte's last value.

// Adds one layer encoder per byte of an item of `size` bytes.
void add_byte14_encoders(const ItemEncodeSetup& setup, std::size_t size,
                         std::vector<std::unique_ptr<LayerEncoder>>& out);

}  // namespace lidarscout::laz::detail::point14
