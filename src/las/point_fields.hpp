// A bit mask naming the fields of a point record, for readers that can decode only some of them
// (the LAZ decoder skips the layers of fields nobody asked for). Bytes of fields not asked for are
// left zero in the records handed back; XYZ is always decoded (every other field's context
// depends on it), and an uncompressed LAS file always gives every field.
#pragma once

#include <cstdint>

namespace lidarscout::las::fields {

inline constexpr std::uint32_t kXyz = 1u << 0;
inline constexpr std::uint32_t kIntensity = 1u << 1;
inline constexpr std::uint32_t kReturns = 1u << 2;  // return number / count, scan flags
// The class code. In point formats 0-5 the classification flags share its byte and come with it;
// in formats 6-10 (and their layered chunks) they are kClassFlags, a layer of their own.
inline constexpr std::uint32_t kClassification = 1u << 3;
inline constexpr std::uint32_t kScanAngle = 1u << 4;
inline constexpr std::uint32_t kUserData = 1u << 5;
inline constexpr std::uint32_t kPointSource = 1u << 6;
inline constexpr std::uint32_t kGpsTime = 1u << 7;
inline constexpr std::uint32_t kRgb = 1u << 8;
inline constexpr std::uint32_t kNir = 1u << 9;
inline constexpr std::uint32_t kWavepacket = 1u << 10;
inline constexpr std::uint32_t kExtraBytes = 1u << 11;
inline constexpr std::uint32_t kClassFlags = 1u << 12;           // synthetic, key-point, withheld, overlap
inline constexpr std::uint32_t kEvery = (kClassFlags << 1) - 1;  // every bit above
inline constexpr std::uint32_t kAll = 0xFFFFFFFFu;

}  // namespace lidarscout::las::fields
