// What the decoder (rgbnir14_v3.cpp) and the encoder (rgbnir14_v3_encoder.cpp) of the NIR
// layer of RGBNIR14 share, defined once: the value, how it is read from a raw item, and the
// models of a channel context. (The colour layer is RGB14's, see rgb14_v3_state.hpp.)
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>

#include "laz/arithmetic_models.hpp"
#include "laz/point14/layer_common.hpp"

namespace lidarscout::laz::point14 {

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

}  // namespace lidarscout::laz::point14
