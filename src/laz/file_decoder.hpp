// Decoding the points of a LAZ file: its decode units (the chunks of the chunk table, or one
// unit spanning the point data of a compressor-1 file), read with positioned reads and
// decoded in parallel on the library's thread pool. Errors name the file and the chunk.
#pragma once

#include <cstdint>
#include <functional>
#include <span>
#include <vector>

#include "las/header.hpp"
#include "las/laszip_vlr.hpp"
#include "laz/chunk_decoder.hpp"
#include "laz/chunk_table.hpp"

namespace lidarscout {
class ThreadPool;
}
namespace lidarscout::io {
class File;
}

namespace lidarscout::laz {

// What a LAZ file needs for decoding (all read beforehand from its header and VLRs).
struct LazLayout {
    las::Header header;
    las::LaszipVlr laz;
    std::vector<Chunk> units;  // decode units in file order, with first_point set
};

// The decode units: the chunk table's chunks, or for compressor 1 one unit from the point
// data offset to the end of the point data (the EVLRs, else the end of the file).
std::vector<Chunk> decode_units(const las::Header& header, const las::LaszipVlr& laz, const ChunkTable& table,
                                std::uint64_t file_size);

// Decodes unit `index` of `layout` into `out` (unit.point_count * record_length bytes).
// `scratch` holds the compressed bytes between calls (no allocation per chunk once grown).
void decode_unit(const io::File& file, const LazLayout& layout, std::size_t index, std::span<std::uint8_t> out,
                 std::uint32_t fields, std::vector<std::uint8_t>& scratch);

// Decodes the units [first, last) in parallel into `out` (their records back to back).
void decode_units_parallel(const io::File& file, const LazLayout& layout, std::size_t first, std::size_t last,
                           std::span<std::uint8_t> out, std::uint32_t fields, ThreadPool& pool);

}  // namespace lidarscout::laz
