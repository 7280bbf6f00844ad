// Encoder of the GPSTIME11 item, version 2: the inverse of GpsTime11DecoderV2. It keeps
// the same four time sequences and picks, for every time, the symbol LASzip's writer picks:
// unchanged, a multiple of the sequence's last delta (the multiple rounded from a
// single-precision quotient, as LASzip computes it), a switch to another sequence whose
// time is within 32 bits, or a new sequence coded in full.
#pragma once

#include <cstdint>
#include <limits>
#include <optional>

#include "laz/arithmetic_encoder.hpp"
#include "laz/integer_compressor.hpp"
#include "laz/point10/gpstime11_v2_state.hpp"
#include "laz/point10/item_common.hpp"
#include "laz/point10/symbols_v2.hpp"

namespace lidarscout::laz::point10 {

// A difference of two times (bit patterns) as an int32, if it fits: a delta that can be coded.
inline std::optional<std::int32_t> gps_delta_as_int32(std::uint64_t difference) {
    const auto d = static_cast<std::int64_t>(difference);
    if (d < std::numeric_limits<std::int32_t>::min() || d > std::numeric_limits<std::int32_t>::max()) {
        return std::nullopt;
    }
    return static_cast<std::int32_t>(d);
}

// The multiple of `last_delta` (not 0) that `delta` is, rounded half away from zero the
// way LASzip does it: the quotient in single precision, the rounding in double, and a
// quotient outside the int32 range giving INT32_MIN (what an x86-64 build of LASzip gets
// from that conversion).
std::int32_t gps_delta_multiple(std::int32_t delta, std::int32_t last_delta);

// The state (sequences, models) is GpsTime11StateV2's, shared with the decoder.
class GpsTime11EncoderV2 : private GpsTime11StateV2<IntegerCompressor> {
public:
    static constexpr std::size_t kSize = 8;

    GpsTime11EncoderV2();

    // Starts a chunk whose first (raw) time is at `first`.
    using GpsTime11StateV2::init;

    void encode(ArithmeticEncoder& enc, const std::uint8_t* item) { encode_time(enc, load<std::uint64_t>(item)); }

private:
    void encode_time(ArithmeticEncoder& enc, std::uint64_t time);
    // Codes a non-zero 32-bit `delta` of the current sequence, whose last delta is not 0.
    void encode_delta(ArithmeticEncoder& enc, std::int32_t delta);
    // Opens a new sequence for `time` (upper half predicted, lower half raw).
    void start_new_sequence(ArithmeticEncoder& enc, std::uint64_t time);
    // Offset (1..3) of another sequence whose last time is within 32 bits of `time`; 0 if none.
    std::uint32_t find_other_sequence(std::uint64_t time) const;
};

}  // namespace lidarscout::laz::point10
