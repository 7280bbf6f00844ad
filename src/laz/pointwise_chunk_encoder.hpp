// Encoding of point-wise chunked LAZ data (compressor 2) with the point10-family items that
// LASzip writes for LAS point formats 0-5: POINT10, then optionally GPSTIME11, RGB12 (all v2),
// WAVEPACKET13 (v1) and BYTE (v2, extra bytes), in that order. The mirror of
// decode_pointwise_chunk.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "las/laszip_vlr.hpp"

namespace lidarscout::laz {

// Appends one chunk to `out`: the first of `point_count` (>= 1) records raw, then one
// arithmetic-coded stream of the others, byte-identical to LASzip's. Throws
// lidarscout::Error for another item list or records whose size does not match.
void encode_pointwise_chunk(const las::LaszipVlr& laz, std::span<const std::uint8_t> records,
                            std::uint64_t point_count, std::vector<std::uint8_t>& out);

}  // namespace lidarscout::laz
