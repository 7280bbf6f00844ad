// What decoding a tile into LOD blocks holds besides the blocks it adds, so that the residency
// admits a decode only when it fits in the budget. Each decoding thread works on one piece at a
// time (point_sets.hpp: whole decode units, `piece_points` rounded up to the next unit) and, per
// point of its piece, holds the raw records and the converted points while decoding, then the
// converted points, the block index and each block's sort keys and levels while building the
// piece's blocks (point_lod.cpp). A smaller piece holds less; the smallest is one unit per thread.
#pragma once

#include <cstdint>
#include <optional>

#include "dataset/dataset.hpp"

namespace lidarscout::viewer {

// Bytes a decoding thread holds per point of its piece, the blocks it becomes not included.
std::uint64_t piece_bytes_per_point(const dataset::DatasetTile& tile);

// Points of the tile's largest decode unit: a LAZ chunk, or the whole tile when it decodes as
// one piece (LAS, LAZ without a chunk table).
std::uint64_t largest_unit_points(const dataset::DatasetTile& tile);

struct DecodePlan {
    std::uint64_t piece_points = 0;  // asked of decode_tile_pieces
    std::uint64_t transient = 0;     // bytes the decoding threads hold at most together, blocks not included
};

// What decoding `points` points of `tile` on `threads` threads holds with pieces of
// `piece_points` points.
DecodePlan decode_plan(const dataset::DatasetTile& tile, std::uint64_t points, unsigned threads,
                       std::uint64_t piece_points);

// The plan with the largest pieces (at most `max_piece_points`, halved until it fits) whose
// transient bytes fit in `room`; nullopt when even one unit per thread does not.
std::optional<DecodePlan> fitting_decode_plan(const dataset::DatasetTile& tile, std::uint64_t points, unsigned threads,
                                              std::uint64_t max_piece_points, std::uint64_t room);

}  // namespace lidarscout::viewer
