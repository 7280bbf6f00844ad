// Symbol numbers, mask bits and coder contexts of the v2 point10-family items, shared by
// their decoders and encoders: both sides must agree on every one of them, so they are
// defined once, here.
#pragma once

#include <cstdint>

namespace lidarscout::laz::point10 {

// POINT10 v2: bits of the change mask (which attributes differ from the last point).
namespace point10_v2 {
inline constexpr std::uint32_t kChangedPointSource = 1u << 0;
inline constexpr std::uint32_t kChangedUserData = 1u << 1;
inline constexpr std::uint32_t kChangedScanAngle = 1u << 2;
inline constexpr std::uint32_t kChangedClassification = 1u << 3;
inline constexpr std::uint32_t kChangedIntensity = 1u << 4;
inline constexpr std::uint32_t kChangedReturnFlags = 1u << 5;
inline constexpr std::uint32_t kChangeMaskSymbols = 64;
}  // namespace point10_v2

// RGB12 v2: bits 0-5 of the mask flag the changed colour bytes (byte i of the item); bit 6
// says that green and blue differ from red.
namespace rgb12_v2 {
inline constexpr std::uint32_t kNotGrey = 1u << 6;
inline constexpr std::uint32_t kMaskSymbols = 128;
}  // namespace rgb12_v2

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

}  // namespace lidarscout::laz::point10
