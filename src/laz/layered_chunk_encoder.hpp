// Encoding of one layered LAZ chunk (compressor 3: LAS 1.4 point formats 6-10 with items
// POINT14, RGB14 or RGBNIR14, WAVEPACKET14 and BYTE14, all in version 3), the mirror of
// decode_layered_chunk and byte-identical to what LASzip writes: the first record raw, the
// chunk's point count (u32), the byte size of every layer (u32 each, in item order, then
// layer order), then the layers' arithmetic-coded streams. A layer whose field never
// changes in the chunk is stored empty.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "las/laszip_vlr.hpp"

namespace lidarscout::laz {

// Appends the chunk of `point_count` (>= 1) records (laz.record_length() bytes each) to
// `out`. Throws lidarscout::Error for another compressor or item list (item versions other
// than 3 are not written) or records whose size does not match.
void encode_layered_chunk(const las::LaszipVlr& laz, std::span<const std::uint8_t> records, std::uint64_t point_count,
                          std::vector<std::uint8_t>& out);

}  // namespace lidarscout::laz
