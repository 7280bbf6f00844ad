// What the decoder (byte14_v3.cpp) and the encoder (byte14_v3_encoder.cpp) of a BYTE14
// layer (one extra byte) share, defined once: the value, how it is read from a raw item,
// and the model of a channel context.
#pragma once

#include <cstddef>
#include <cstdint>

#include "laz/arithmetic_models.hpp"

namespace lidarscout::laz::point14 {

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

}  // namespace lidarscout::laz::point14
