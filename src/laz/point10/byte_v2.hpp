// Decoder of the BYTE item (extra bytes), version 2: every byte is coded as a difference
// to its last value under its own 256-symbol model.
#pragma once

#include <cstdint>
#include <vector>

#include "laz/arithmetic_decoder.hpp"
#include "laz/point10/item_common.hpp"

namespace lidarscout::laz::point10 {

class ByteDecoderV2 {
public:
    // `size`: bytes in the item (at least 1).
    explicit ByteDecoderV2(std::size_t size);

    // Starts a chunk whose first (raw) bytes are at `first`.
    void init(const std::uint8_t* first);

    void decode(ArithmeticDecoder& dec, std::uint8_t* out) {
        for (std::size_t i = 0; i < last_.size(); ++i) {
            last_[i] = wrap_byte(static_cast<std::int32_t>(dec.decode_symbol(models_[i]) + last_[i]));
        }
        std::memcpy(out, last_.data(), last_.size());
    }

private:
    std::vector<std::uint8_t> last_;
    std::vector<SymbolModel> models_;
};

}  // namespace lidarscout::laz::point10
