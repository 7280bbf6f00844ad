// Encoding raw LAS point records into one LAZ chunk, the mirror of decode_chunk: the bytes
// are exactly what LASzip writes for that chunk, so a file assembled from them (with
// encode_chunk_table and the VLR of make_laszip_vlr) is what LASzip would have written.
// Chunks are independent: callers encode them in parallel.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "las/laszip_vlr.hpp"

namespace lidarscout::laz {

// Encodes point_count raw LAS records (record_length each) as one chunk: first record raw,
// then the coded stream. Appends to `out`. Dispatches on laz.compressor: 2 (point-wise
// chunked, point formats 0-5); 3 (layered, formats 6-10). Throws
// lidarscout::Error for unsupported item lists or a record span of the wrong size.
void encode_chunk(const las::LaszipVlr& laz, std::span<const std::uint8_t> records, std::uint64_t point_count,
                  std::vector<std::uint8_t>& out);

}  // namespace lidarscout::laz
