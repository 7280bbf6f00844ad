// Encoder of the BYTE item (extra bytes), version 2: the inverse of ByteDecoderV2, every
// byte coded as its difference to the last value under its own 256-symbol model.
#pragma once

#include <cstdint>
#include <vector>

#include "laz/arithmetic_encoder.hpp"
#include "laz/point10/item_common.hpp"

namespace lidarscout::laz::point10 {

class ByteEncoderV2 {
public:
    // `size`: bytes in the item (at least 1).
    explicit ByteEncoderV2(std::size_t size);

    // Starts a chunk whose first (raw) bytes are at `first`.
    void init(const std::uint8_t* first);

    void encode(ArithmeticEncoder& enc, const std::uint8_t* item) {
        for (std::size_t i = 0; i < last_.size(); ++i) {
            enc.encode_symbol(models_[i], wrap_byte(item[i] - last_[i]));
            last_[i] = item[i];
        }
    }

private:
    std::vector<std::uint8_t> last_;
    std::vector<SymbolModel> models_;
};

}  // namespace lidarscout::laz::point10
