// Chunk points: the sparse overview of a tile without decompression. For LAZ, the first
// point of every chunk is stored raw at the chunk's start; for LAS, every N-th record.
#pragma once

#include <cstdint>
#include <vector>

#include "las/point_format.hpp"

namespace lidarscout::io {
class File;
}

namespace lidarscout::dataset {

struct Tile;

// The sampling stride used for uncompressed LAS files (the usual LAZ chunk size).
inline constexpr std::uint64_t kLasChunkPointStride = 50'000;

struct ChunkPoint {
    std::uint64_t index = 0;  // index of the point in the file
    las::Point point;         // decoded, with coordinates in the tile's CRS
};

// Where a chunk point lies: its index in the file and the byte offset of its raw record.
struct ChunkPointLocation {
    std::uint64_t index = 0;
    std::uint64_t offset = 0;
};

// The chunk points of `tile` without reading them: for LAZ the start of every non-empty
// decode unit (the chunk table must have been read), for LAS every `las_stride`-th record.
std::vector<ChunkPointLocation> chunk_point_locations(const Tile& tile,
                                                      std::uint64_t las_stride = kLasChunkPointStride);

// Reads the chunk points of `tile` with one positioned read per point. For LAZ the tile's
// chunk table must have been read (TileOptions::chunk_table).
std::vector<ChunkPoint> read_chunk_points(const io::File& file, const Tile& tile,
                                          std::uint64_t las_stride = kLasChunkPointStride);

// The chunk points of `tile`: from the records an overview sidecar holds for it (no read; see
// dataset/overview_sidecar.hpp), else read from its file (read_chunk_points).
std::vector<ChunkPoint> tile_chunk_points(const Tile& tile, std::uint64_t las_stride = kLasChunkPointStride);

// How many chunk points read_chunk_points would return (no point reads).
std::uint64_t chunk_point_count(const Tile& tile, std::uint64_t las_stride = kLasChunkPointStride);

}  // namespace lidarscout::dataset
