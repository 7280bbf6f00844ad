// Decoder of the GPSTIME11 item, version 1: one time sequence predicted from the last
// 32-bit delta and a coded multiple of it; large jumps are stored as raw 64-bit values.
#pragma once

#include <cstdint>

#include "laz/arithmetic_decoder.hpp"
#include "laz/integer_decompressor.hpp"
#include "laz/items/item_common.hpp"

namespace lidarscout::laz::detail::point10 {

class GpsTime11DecoderV1 {
public:
    static constexpr std::size_t kSize = 8;

    GpsTime11DecoderV1();

    // Starts a chunk whose first (raw) time is at `first`.
    void init(const std::uint8_t* first);

    void decode(ArithmeticDecoder& dec, std::uint8_t* out) {
        decode_time(dec);
        store(out, time_);
    }

private:
    void decode_time(ArithmeticDecoder& dec);

    std::uint64_t time_ = 0;  // bit pattern of the double
    std::int32_t delta_ = 0;
    std::int32_t extreme_count_ = 0;

    SymbolModel multiple_model_;
    SymbolModel after_zero_model_{3};
    IntegerDecompressor delta_coder_{32, 6};
};

}  // namespace lidarscout::laz::detail::point10
