// The GPSTIME11 item, version 2 (point-wise chunks): one file set (gpstime11_v2.hpp/.cpp) holds all of this item
// version, nothing of it lives elsewhere: its symbols, the state its decoder and encoder
// share, the decoder and the encoder.
#pragma once

#include <array>
#include <cstdint>
#include <limits>
#include <optional>

#include "laz/arithmetic_decoder.hpp"
#include "laz/arithmetic_encoder.hpp"
#include "laz/arithmetic_models.hpp"
#include "laz/integer_compressor.hpp"
#include "laz/integer_decompressor.hpp"
#include "laz/items/item_common.hpp"

namespace lidarscout::laz::detail::point10 {

// ---- Symbols and contexts (the decoder and the encoder agree on them by construction)
// GPSTIME11 v2.
namespace gpstime11_v2 {
// Symbols of the multiple model: 0 .. kMaxMultiple are multiples (0 stands for "large"),
// then -1 .. kMinMultiple + 1 (coded as kMaxMultiple - m) and an extreme negative
// multiple, then "unchanged", "coded in full", and switches to the three other sequences.
inline constexpr std::int32_t kMaxMultiple = 500;
inline constexpr std::int32_t kMinMultiple = -10;
inline constexpr std::uint32_t kUnchanged = kMaxMultiple - kMinMultiple + 1;
inline constexpr std::uint32_t kFull = kMaxMultiple - kMinMultiple + 2;
inline constexpr std::uint32_t kMultipleSymbols = kMaxMultiple - kMinMultiple + 6;

// Symbols of the model used after a zero delta: 0 unchanged, 1 a 32-bit delta, 2 coded
// in full, 3..5 switches to the other sequences.
inline constexpr std::uint32_t kAfterZeroUnchanged = 0;
inline constexpr std::uint32_t kAfterZeroDelta = 1;
inline constexpr std::uint32_t kAfterZeroFull = 2;
inline constexpr std::uint32_t kAfterZeroSwitch = 3;
inline constexpr std::uint32_t kAfterZeroSymbols = 6;

// Multiples below this use their own delta context.
inline constexpr std::int32_t kSmallMultipleLimit = 10;

// Contexts of the delta coder.
inline constexpr std::uint32_t kCtxFirstDelta = 0;
inline constexpr std::uint32_t kCtxSameDelta = 1;
inline constexpr std::uint32_t kCtxSmallMultiple = 2;
inline constexpr std::uint32_t kCtxMultiple = 3;
inline constexpr std::uint32_t kCtxMaxMultiple = 4;
inline constexpr std::uint32_t kCtxNegativeMultiple = 5;
inline constexpr std::uint32_t kCtxMinMultiple = 6;
inline constexpr std::uint32_t kCtxLarge = 7;
inline constexpr std::uint32_t kCtxUpperHalf = 8;
inline constexpr std::uint32_t kDeltaContexts = 9;

// A sequence whose delta needed an extreme multiple more than this many times in a row
// takes the last delta as its new reference.
inline constexpr std::int32_t kMaxExtremeCount = 3;
}  // namespace gpstime11_v2

// ---- State shared by the decoder and the encoder
// The state that the GPSTIME11 v2 decoder and encoder keep across a chunk, defined once
// for both: the four time sequences (last time, reference delta, run of extreme multiples),
// the current and newest sequence, the models, the reset at chunk start and the sequence
// bookkeeping both sides do alike.

// The decoder and the encoder derive from this; `IntegerCoder` is IntegerDecompressor or
// IntegerCompressor.
template <class IntegerCoder>
class GpsTime11StateV2 {
protected:
    // Starts a chunk whose first (raw) time is at `first`: sequence 0 holds it, everything
    // else is back in its start state. Out of line (gpstime11_v2.cpp), as it runs once
    // a chunk, away from the point loops.
    void init(const std::uint8_t* first);

    // Makes the next sequence slot, starting at `time`, the current sequence.
    void open_sequence(std::uint64_t time) {
        newest_ = (newest_ + 1) & 3;
        current_ = newest_;
        time_[current_] = time;
        delta_[current_] = 0;
        extreme_count_[current_] = 0;
    }

    // Takes `delta` as the sequence's new reference delta after several extreme multiples.
    void count_extreme(std::int32_t delta) {
        if (++extreme_count_[current_] > gpstime11_v2::kMaxExtremeCount) {
            delta_[current_] = delta;
            extreme_count_[current_] = 0;
        }
    }

    std::array<std::uint64_t, 4> time_{};  // bit patterns of the doubles
    std::array<std::int32_t, 4> delta_{};
    std::array<std::int32_t, 4> extreme_count_{};
    std::uint32_t current_ = 0;
    std::uint32_t newest_ = 0;

    SymbolModel multiple_model_{gpstime11_v2::kMultipleSymbols};
    SymbolModel after_zero_model_{gpstime11_v2::kAfterZeroSymbols};
    IntegerCoder delta_coder_{32, gpstime11_v2::kDeltaContexts};
};

// ---- Decoder
// Decoder of the GPSTIME11 item, version 2: up to four interleaved time sequences (e.g.
// from alternating scanners), each predicted from its own last time and last 32-bit
// delta; a symbol picks the multiple of the delta, a switch to another sequence, or a
// new time coded in full.

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

// ---- Encoder
// Encoder of the GPSTIME11 item, version 2: the inverse of GpsTime11DecoderV2. It keeps
// the same four time sequences and picks, for every time, the symbol LASzip's writer picks:
// unchanged, a multiple of the sequence's last delta (the multiple rounded from a
// single-precision quotient, as LASzip computes it), a switch to another sequence whose
// time is within 32 bits, or a new sequence coded in full.

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

}  // namespace lidarscout::laz::detail::point10
