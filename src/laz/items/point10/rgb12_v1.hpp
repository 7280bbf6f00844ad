// Decoder of the RGB12 item, version 1: a mask says which of the six colour bytes changed,
// and each changed byte is coded against its last value with its own integer context.
#pragma once

#include <array>
#include <cstdint>

#include "laz/arithmetic_decoder.hpp"
#include "laz/integer_decompressor.hpp"
#include "laz/items/item_common.hpp"

namespace lidarscout::laz::detail::point10 {

class Rgb12DecoderV1 {
public:
    static constexpr std::size_t kSize = 6;

    Rgb12DecoderV1();

    // Starts a chunk whose first (raw) colour is at `first`.
    void init(const std::uint8_t* first);

    void decode(ArithmeticDecoder& dec, std::uint8_t* out) {
        const std::uint32_t mask = dec.decode_symbol(changed_mask_);
        for (std::uint32_t i = 0; i < kSize; ++i) {
            if (mask & (1u << i)) last_[i] = static_cast<std::uint8_t>(byte_coder_.decompress(dec, last_[i], i));
        }
        std::memcpy(out, last_.data(), kSize);
    }

private:
    std::array<std::uint8_t, 6> last_{};
    SymbolModel changed_mask_{64};
    IntegerDecompressor byte_coder_{8, 6};
};

}  // namespace lidarscout::laz::detail::point10
