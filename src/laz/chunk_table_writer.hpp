// Writing the LAZ chunk table, the inverse of read_chunk_table: u32 version 0, u32 chunk
// count, then the entries arithmetic-coded as LASzip codes them (32-bit integers in two
// contexts: the point count, only for variable-size chunks, and the byte count, each
// predicted by the previous chunk's). The caller places it in the file and stores its
// position in the int64 before the first chunk.
#pragma once

#include <cstdint>
#include <vector>

#include "laz/laz.hpp"

namespace lidarscout::laz {

// The table's bytes for `chunks` (only point_count and byte_size are used; point counts
// only when `variable_chunks`). Byte-identical to LASzip's table. Throws lidarscout::Error
// when a count does not fit the table's 32-bit fields.
std::vector<std::uint8_t> encode_chunk_table(const std::vector<Chunk>& chunks, bool variable_chunks);

}  // namespace lidarscout::laz
