// Decoding one LAZ chunk into raw LAS point records (the bytes a LAS file would hold),
// for every compressor: point-wise (1, 2) and layered (3). Chunks are independent, so
// callers decode them in parallel. A subset of fields can be asked for: for layered
// chunks the other layers are then not entropy-decoded at all.
#pragma once

#include <cstdint>
#include <span>

#include "las/laszip_vlr.hpp"

namespace lidarscout::laz {

// Bit mask of point fields a caller needs. Bytes of fields not asked for are left zero
// in the output records (XYZ is always decoded: every other field's context depends on it).
namespace fields {
inline constexpr std::uint32_t kXyz = 1u << 0;
inline constexpr std::uint32_t kIntensity = 1u << 1;
inline constexpr std::uint32_t kReturns = 1u << 2;         // return number / count, scan flags
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
inline constexpr std::uint32_t kClassFlags = 1u << 12;  // synthetic, key-point, withheld, overlap
inline constexpr std::uint32_t kEvery = (kClassFlags << 1) - 1;  // every bit above
inline constexpr std::uint32_t kAll = 0xFFFFFFFFu;
}  // namespace fields

struct ChunkDecodeRequest {
    std::span<const std::uint8_t> bytes;  // the chunk's compressed bytes (byte_offset .. +byte_size)
    std::uint64_t point_count = 0;        // points in this chunk
    std::span<std::uint8_t> out;          // point_count * record_length bytes
    std::uint32_t fields = fields::kAll;
};

// Decodes one chunk; throws lidarscout::Error (cause, offset within the chunk when known;
// no file name: the caller adds file and chunk index) for corrupt or unsupported data.
void decode_chunk(const las::LaszipVlr& laz, const ChunkDecodeRequest& request);

}  // namespace lidarscout::laz
