// Decoder of the BYTE item (extra bytes), version 2: every byte is coded as a difference
// to its last value under its own 256-symbol model.
#pragma once

#include <cstdint>

#include "laz/arithmetic_decoder.hpp"
#include "laz/point10/byte_v2_state.hpp"
#include "laz/point10/item_common.hpp"

namespace lidarscout::laz::point10 {

// The state (last bytes, models) is ByteStateV2's, shared with the encoder.
class ByteDecoderV2 : private ByteStateV2 {
public:
    // `size`: bytes in the item (at least 1).
    explicit ByteDecoderV2(std::size_t size) : ByteStateV2(size) {}

    // Starts a chunk whose first (raw) bytes are at `first`.
    using ByteStateV2::init;

    void decode(ArithmeticDecoder& dec, std::uint8_t* out) {
        for (std::size_t i = 0; i < last_.size(); ++i) {
            last_[i] = wrap_byte(static_cast<std::int32_t>(dec.decode_symbol(models_[i]) + last_[i]));
        }
        std::memcpy(out, last_.data(), last_.size());
    }
};

}  // namespace lidarscout::laz::point10
