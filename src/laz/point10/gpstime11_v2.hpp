// Decoder of the GPSTIME11 item, version 2: up to four interleaved time sequences (e.g.
// from alternating scanners), each predicted from its own last time and last 32-bit
// delta; a symbol picks the multiple of the delta, a switch to another sequence, or a
// new time coded in full.
#pragma once

#include <array>
#include <cstdint>

#include "laz/arithmetic_decoder.hpp"
#include "laz/integer_decompressor.hpp"
#include "laz/point10/item_common.hpp"

namespace lidarscout::laz::point10 {

class GpsTime11DecoderV2 {
public:
    static constexpr std::size_t kSize = 8;

    GpsTime11DecoderV2();

    // Starts a chunk whose first (raw) time is at `first`.
    void init(const std::uint8_t* first);

    void decode(ArithmeticDecoder& dec, std::uint8_t* out) {
        decode_time(dec);
        store(out, time_[current_]);
    }

private:
    // Advances the current sequence (possibly after switching to another one).
    void decode_time(ArithmeticDecoder& dec);
    // Opens a new sequence whose time is coded in full (upper half predicted, lower raw).
    void start_new_sequence(ArithmeticDecoder& dec);
    // Takes `delta` as the sequence's new reference delta after several extreme multiples.
    void count_extreme(std::int32_t delta);

    std::array<std::uint64_t, 4> time_{};  // bit patterns of the doubles
    std::array<std::int32_t, 4> delta_{};
    std::array<std::int32_t, 4> extreme_count_{};
    std::uint32_t current_ = 0;
    std::uint32_t newest_ = 0;

    SymbolModel multiple_model_;
    SymbolModel after_zero_model_{6};
    IntegerDecompressor delta_coder_{32, 9};
};

}  // namespace lidarscout::laz::point10
