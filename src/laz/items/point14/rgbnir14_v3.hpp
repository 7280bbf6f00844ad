// The RGBNIR14 item of layered chunks, versions 3 and 4 (colour layer as RGB14, plus NIR): one file
// set (rgbnir14_v3.hpp/.cpp) holds all of this item version, nothing of it lives elsewhere: its
// symbols, the state its decoder and encoder share, the decoder and the encoder.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <vector>

#include "laz/arithmetic_models.hpp"
#include "laz/items/point14/layer_common.hpp"
#include "laz/items/point14/layer_encoder.hpp"

namespace lidarscout::laz::detail::point14 {

// ---- State shared by the decoder and the encoder
// What the decoder and the encoder (rgbnir14_v3.cpp) of the NIR
// layer of RGBNIR14 share, defined once: the value, how it is read from a raw item, and the
// models of a channel context. (The colour layer is RGB14's, see rgb14_v3.hpp.)

// The codecs derive from this (see ContextLayer and ContextLayerEncoder).
struct NirState {
    using Value = std::uint16_t;
    struct Models {
        SymbolModel changed{4};                                    // bit 0: low byte, bit 1: high byte
        std::array<SymbolModel, 2> bytes = symbol_models<2>(256);  // corrections
        void begin(Value&) {}
    };
    static constexpr std::size_t kNirOffset = 6;

    Value read(const std::uint8_t* item) const { return load<std::uint16_t>(item + kNirOffset); }
};

// ---- Decoder
// Decoder of the RGBNIR14 item of layered chunks (versions 3 and 4): two layers, the colour
// (coded like RGB14) and the near-infrared value, whose two bytes are each either repeated
// or corrected from their last value.
inline constexpr std::size_t kRgbNir14Size = 8;

// Adds the passes of the layers the caller wants (colour, NIR).
void add_rgbnir14_layers(const ItemSetup& setup, std::vector<PlacedLayer>& out);

// ---- Encoder
// Encoder of the RGBNIR14 item, version 3 (the mirror of the decoder above): the colour layer
// (as RGB14) and the NIR layer.

// Adds the item's two layer encoders (colour, NIR).
void add_rgbnir14_encoders(const ItemEncodeSetup& setup, std::vector<std::unique_ptr<LayerEncoder>>& out);

}  // namespace lidarscout::laz::detail::point14
