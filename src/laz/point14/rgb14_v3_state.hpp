// What the decoder (rgb14_v3.cpp) and the encoder (rgb14_v3_encoder.cpp) of the colour
// layer of RGB14 and RGBNIR14 share, defined once: the value, how it is read from a raw
// item, and the models of a channel context.
#pragma once

#include <array>
#include <cstdint>

#include "laz/arithmetic_models.hpp"
#include "laz/point14/layer_common.hpp"

namespace lidarscout::laz::point14 {

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

}  // namespace lidarscout::laz::point14
