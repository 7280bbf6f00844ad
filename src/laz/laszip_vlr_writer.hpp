// The LASzip VLR ("laszip encoded", record 22204) a writer stores: the item list LASzip
// chooses for a point format and record length, and its serialised payload (the inverse of
// las::parse_laszip_vlr).
#pragma once

#include <cstdint>
#include <vector>

#include "las/laszip_vlr.hpp"

namespace lidarscout::laz {

// The LASzip version our files claim to be written by (the one of the reference files).
inline constexpr std::uint8_t kWriterVersionMajor = 3;
inline constexpr std::uint8_t kWriterVersionMinor = 4;
inline constexpr std::uint16_t kWriterVersionRevision = 3;

// The VLR LASzip writes for `point_format` (0-10) with records of `record_length` bytes
// (any bytes beyond the format's size are extra bytes) and chunks of `chunk_size` points
// (LaszipVlr::kVariableChunkSize for variable-size chunks). Formats 0-5: compressor 2 with
// POINT10, GPSTIME11, RGB12, BYTE in version 2 (WAVEPACKET13 in version 1); formats 6-10:
// compressor 3 with POINT14, RGB14 or RGBNIR14, WAVEPACKET14, BYTE14 in version 3.
// Throws lidarscout::Error for an unknown format, a record shorter than the format, or a
// chunk size of 0.
las::LaszipVlr make_laszip_vlr(std::uint8_t point_format, std::uint16_t record_length, std::uint32_t chunk_size);

// The VLR payload: 34 bytes of fixed fields, then 6 bytes per item (all little-endian).
std::vector<std::uint8_t> serialize_laszip_vlr(const las::LaszipVlr& laz);

}  // namespace lidarscout::laz
