// Symbols, contexts and context tables of the layered (point14) item coders, versions 3
// and 4, shared by the decoders and the encoders so both sides agree by construction.
#pragma once

#include <cstdint>

namespace lidarscout::laz::point14 {

// ---- POINT14 returns/XY layer -------------------------------------------------------------

// Bits of the change symbol (128 symbols) that opens every point.
inline constexpr std::uint32_t kReturnStepMask = 3u;  // 0 same, 1 +1, 2 -1, 3 coded
inline constexpr std::uint32_t kReturnsChanged = 1u << 2;
inline constexpr std::uint32_t kChangedShift = 3;  // bits 3-5: scan angle, GPS time, point source (PointTrace order)
inline constexpr std::uint32_t kChannelChanged = 1u << 6;

// Context of the X/Y medians for [number of returns][return number]: six classes that
// separate single, first, last and intermediate returns (out-of-spec pairs included).
inline constexpr std::uint8_t kReturnClass[16][16] = {
    {0, 1, 2, 3, 4, 5, 3, 4, 4, 5, 5, 5, 5, 5, 5, 5}, {1, 0, 1, 3, 3, 3, 3, 3, 3, 3, 3, 3, 3, 3, 3, 3},
    {2, 1, 2, 4, 4, 4, 4, 4, 4, 4, 4, 3, 3, 3, 3, 3}, {3, 3, 4, 5, 4, 4, 4, 4, 4, 4, 4, 4, 4, 4, 4, 4},
    {4, 3, 4, 4, 5, 4, 4, 4, 4, 4, 4, 4, 4, 4, 4, 4}, {5, 3, 4, 4, 4, 5, 4, 4, 4, 4, 4, 4, 4, 4, 4, 4},
    {3, 3, 4, 4, 4, 4, 5, 4, 4, 4, 4, 4, 4, 4, 4, 4}, {4, 3, 4, 4, 4, 4, 4, 5, 4, 4, 4, 4, 4, 4, 4, 4},
    {4, 3, 4, 4, 4, 4, 4, 4, 5, 4, 4, 4, 4, 4, 4, 4}, {5, 3, 4, 4, 4, 4, 4, 4, 4, 5, 4, 4, 4, 4, 4, 4},
    {5, 3, 4, 4, 4, 4, 4, 4, 4, 4, 5, 4, 4, 4, 4, 4}, {5, 3, 3, 4, 4, 4, 4, 4, 4, 4, 4, 5, 5, 4, 4, 4},
    {5, 3, 3, 4, 4, 4, 4, 4, 4, 4, 4, 5, 5, 5, 4, 4}, {5, 3, 3, 4, 4, 4, 4, 4, 4, 4, 4, 4, 5, 5, 5, 4},
    {5, 3, 3, 4, 4, 4, 4, 4, 4, 4, 4, 4, 4, 5, 5, 5}, {5, 3, 3, 4, 4, 4, 4, 4, 4, 4, 4, 4, 4, 4, 5, 5},
};

// Return level (Z context): how many returns separate r from n, capped at 7.
inline std::uint32_t return_level(std::uint32_t returns, std::uint32_t r) {
    const std::uint32_t gap = returns > r ? returns - r : r - returns;
    return gap < 7 ? gap : 7;
}

// Integer-coder context from a corrector size class: even classes below `cap`, else cap.
inline std::uint32_t size_context(std::uint32_t k, std::uint32_t cap) { return k < cap ? (k & ~1u) : cap; }

// ---- POINT14 GPS time layer ----------------------------------------------------------------

// Symbols of the "multiple" model: 0 (a delta coded on its own), 1 .. 500 (that multiple
// of the reference delta), 501 .. 510 (multiples -1 .. -10), 511 (a new sequence), 512 .. 514
// (switch to the sequence 1 .. 3 places further).
inline constexpr std::int32_t kLargestMultiple = 500;
inline constexpr std::int32_t kSmallestMultiple = -10;
inline constexpr std::uint32_t kNewSequence = kLargestMultiple - kSmallestMultiple + 1;  // 511
inline constexpr std::uint32_t kMultipleSymbols = kNewSequence + 4;
// After a zero delta a smaller model: 0 (a coded delta), 1 (new sequence), 2 .. 4 (switch).
inline constexpr std::uint32_t kAfterZeroSymbols = 5;
// Extreme multiples in a row after which the coded delta becomes the reference.
inline constexpr std::int32_t kExtremeRunLimit = 3;

// Integer-coder contexts of the delta coder.
enum DeltaContext : std::uint32_t {
    kAfterZero = 0, kSameDelta = 1, kSmallMultiple = 2, kLargeMultiple = 3, kLargestMult = 4,
    kNegativeMultiple = 5, kSmallestMult = 6, kOwnDelta = 7, kUpperHalf = 8,
};

// ---- RGB14 / RGBNIR14 colour layer ---------------------------------------------------------

inline constexpr std::uint32_t kNotGrey = 1u << 6;  // green and blue are coded, not copies of red

// Symbol bits of the six bytes: red low/high, green low/high, blue low/high.
inline constexpr std::uint32_t kRedLow = 1u << 0, kRedHigh = 1u << 1, kGreenLow = 1u << 2, kGreenHigh = 1u << 3,
                               kBlueLow = 1u << 4, kBlueHigh = 1u << 5;

}  // namespace lidarscout::laz::point14
