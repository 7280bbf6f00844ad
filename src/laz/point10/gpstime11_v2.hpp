// Decoder of the GPSTIME11 item, version 2: up to four interleaved time sequences (e.g.
// from alternating scanners), each predicted from its own last time and last 32-bit
// delta; a symbol picks the multiple of the delta, a switch to another sequence, or a
// new time coded in full.
#pragma once

#include <cstdint>

#include "laz/arithmetic_decoder.hpp"
#include "laz/integer_decompressor.hpp"
#include "laz/point10/gpstime11_v2_state.hpp"
#include "laz/point10/item_common.hpp"

namespace lidarscout::laz::point10 {

// The state (sequences, models) is GpsTime11StateV2's, shared with the encoder.
class GpsTime11DecoderV2 : private GpsTime11StateV2<IntegerDecompressor> {
public:
    static constexpr std::size_t kSize = 8;

    GpsTime11DecoderV2();

    // Starts a chunk whose first (raw) time is at `first`.
    using GpsTime11StateV2::init;

    void decode(ArithmeticDecoder& dec, std::uint8_t* out) {
        decode_time(dec);
        store(out, time_[current_]);
    }

private:
    // Advances the current sequence (possibly after switching to another one).
    void decode_time(ArithmeticDecoder& dec);
    // Opens a new sequence whose time is coded in full (upper half predicted, lower raw).
    void start_new_sequence(ArithmeticDecoder& dec);
};

}  // namespace lidarscout::laz::point10
