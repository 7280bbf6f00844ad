// Decoder of the BYTE item (extra bytes), version 1: every byte is coded against its last
// value by one integer coder with a context per byte position.
#pragma once

#include <cstdint>
#include <vector>

#include "laz/arithmetic_decoder.hpp"
#include "laz/integer_decompressor.hpp"
#include "laz/items/item_common.hpp"

namespace lidarscout::laz::detail::point10 {

class ByteDecoderV1 {
public:
    // `size`: bytes in the item (at least 1).
    explicit ByteDecoderV1(std::size_t size);

    // Starts a chunk whose first (raw) bytes are at `first`.
    void init(const std::uint8_t* first);

    void decode(ArithmeticDecoder& dec, std::uint8_t* out) {
        for (std::size_t i = 0; i < last_.size(); ++i) {
            last_[i] = static_cast<std::uint8_t>(coder_.decompress(dec, last_[i], static_cast<std::uint32_t>(i)));
        }
        std::memcpy(out, last_.data(), last_.size());
    }

private:
    std::vector<std::uint8_t> last_;
    IntegerDecompressor coder_;
};

}  // namespace lidarscout::laz::detail::point10
