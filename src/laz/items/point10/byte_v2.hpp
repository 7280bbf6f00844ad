// The BYTE item (extra bytes), version 2 (point-wise chunks): one file set (byte_v2.hpp/.cpp) holds all of this item
// version, nothing of it lives elsewhere: its symbols, the state its decoder and encoder
// share, the decoder and the encoder.
#pragma once

#include <cstdint>
#include <vector>

#include "laz/arithmetic_decoder.hpp"
#include "laz/arithmetic_encoder.hpp"
#include "laz/arithmetic_models.hpp"
#include "laz/items/item_common.hpp"

namespace lidarscout::laz::detail::point10 {

// ---- State shared by the decoder and the encoder
// The state that the BYTE v2 (extra bytes) decoder and encoder keep across a chunk, defined
// once for both: the last value and the model of every byte, and the reset at chunk start.

// The decoder and the encoder derive from this.
class ByteStateV2 {
protected:
    // `size`: bytes in the item (at least 1).
    explicit ByteStateV2(std::size_t size);

    // Starts a chunk whose first (raw) bytes are at `first`.
    void init(const std::uint8_t* first);

    std::vector<std::uint8_t> last_;
    std::vector<SymbolModel> models_;
};

// ---- Decoder
// Decoder of the BYTE item (extra bytes), version 2: every byte is coded as a difference
// to its last value under its own 256-symbol model.

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

// ---- Encoder
// Encoder of the BYTE item (extra bytes), version 2: the inverse of ByteDecoderV2, every
// byte coded as its difference to the last value under its own 256-symbol model.

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

}  // namespace lidarscout::laz::detail::point10
