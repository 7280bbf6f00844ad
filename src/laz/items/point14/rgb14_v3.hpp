// The RGB14 item of layered chunks, versions 3 and 4 (and the colour layer RGBNIR14 shares): one
// file set (rgb14_v3.hpp/.cpp) holds all of this item version, nothing of it lives elsewhere: its
// symbols, the state its decoder and encoder share, the decoder and the encoder.
#pragma once

#include <array>
#include <cstdint>
#include <memory>
#include <span>
#include <vector>

#include "laz/arithmetic_models.hpp"
#include "laz/items/point14/layer_common.hpp"
#include "laz/items/point14/layer_encoder.hpp"

namespace lidarscout::laz::detail::point14 {

// ---- Symbols and contexts (the decoder and the encoder agree on them by construction)
// ---- RGB14 / RGBNIR14 colour layer ---------------------------------------------------------

inline constexpr std::uint32_t kNotGrey = 1u << 6;  // green and blue are coded, not copies of red

// Symbol bits of the six bytes: red low/high, green low/high, blue low/high.
inline constexpr std::uint32_t kRedLow = 1u << 0, kRedHigh = 1u << 1, kGreenLow = 1u << 2, kGreenHigh = 1u << 3,
                               kBlueLow = 1u << 4, kBlueHigh = 1u << 5;

// ---- State shared by the decoder and the encoder
// What the decoder and the encoder (rgb14_v3.cpp) of the colour
// layer of RGB14 and RGBNIR14 share, defined once: the value, how it is read from a raw
// item, and the models of a channel context.

// The codecs derive from this (see ContextLayer and ContextLayerEncoder).
struct RgbState {
    using Value = std::array<std::uint16_t, 3>;
    struct Models {
        SymbolModel changed{128};
        std::array<SymbolModel, 6> bytes = symbol_models<6>(256);  // corrections, by byte
        void begin(Value&) {}
    };

    Value read(const std::uint8_t* item) const {
        return {load<std::uint16_t>(item), load<std::uint16_t>(item + 2), load<std::uint16_t>(item + 4)};
    }

    // The bytes of a channel, each predicted and coded on its own.
    static std::int32_t low(std::uint16_t v) { return v & 0xFF; }
    static std::int32_t high(std::uint16_t v) { return v >> 8; }
};

// ---- Decoder
// Decoder of the RGB14 item of layered chunks (versions 3 and 4; one layer), and the colour
// layer that RGBNIR14 shares. A 7-bit symbol says which of the six colour bytes changed and
// whether the colour is grey; red's bytes are coded against the last red, green's and
// blue's against their last value shifted by red's (and, for blue, green's) change.
inline constexpr std::size_t kRgb14Size = 6;

// The pass of a colour layer (16-bit R, G, B at the start of the item).
PlacedLayer make_rgb_layer(std::span<const std::uint8_t> stream, const ItemSetup& setup);

// Adds the RGB14 item's layer pass if the caller wants colour.
void add_rgb14_layers(const ItemSetup& setup, std::vector<PlacedLayer>& out);

// ---- Encoder
// Encoders of the RGB14 item (one colour layer) and of the colour layer RGBNIR14 shares
// with it, version 3: the mirror of the decoder above.

// The encoder of a colour layer (16-bit R, G, B at the start of the item).
std::unique_ptr<LayerEncoder> make_rgb_encoder(const ItemEncodeSetup& setup);

// Adds the RGB14 item's layer encoder.
void add_rgb14_encoders(const ItemEncodeSetup& setup, std::vector<std::unique_ptr<LayerEncoder>>& out);

}  // namespace lidarscout::laz::detail::point14
