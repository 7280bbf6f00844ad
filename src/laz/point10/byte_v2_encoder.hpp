// Encoder of the BYTE item (extra bytes), version 2: the inverse of ByteDecoderV2, every
// byte coded as its difference to the last value under its own 256-symbol model.
#pragma once

#include <cstdint>

#include "laz/arithmetic_encoder.hpp"
#include "laz/point10/byte_v2_state.hpp"
#include "laz/point10/item_common.hpp"

namespace lidarscout::laz::point10 {

// The state (last bytes, models) is ByteStateV2's, shared with the decoder.
class ByteEncoderV2 : private ByteStateV2 {
public:
    // `size`: bytes in the item (at least 1).
    explicit ByteEncoderV2(std::size_t size) : ByteStateV2(size) {}

    // Starts a chunk whose first (raw) bytes are at `first`.
    using ByteStateV2::init;

    void encode(ArithmeticEncoder& enc, const std::uint8_t* item) {
        for (std::size_t i = 0; i < last_.size(); ++i) {
            enc.encode_symbol(models_[i], wrap_byte(item[i] - last_[i]));
            last_[i] = item[i];
        }
    }
};

}  // namespace lidarscout::laz::point10
