// The memory a dataset's metadata holds: its tiles (headers, COPC info, placement), the parts they
// share (each file's TileFile, alike records: dataset/tile.hpp) counted once, and its lists of
// skipped files and warnings. For memory budgets: a country-sized dataset must leave the memory to
// the points (bench_view prints the bytes per tile).
#pragma once

#include <cstdint>

namespace lidarscout::dataset {

struct Dataset;

// The bytes `dataset`'s metadata holds: the tile vector's capacity, and what the parts own on the
// heap (containers by their capacity, strings beyond their inline buffer), each shared part once.
// Neither the allocator's overhead per block nor the PROJ transforms to the frame are counted.
std::uint64_t metadata_bytes(const Dataset& dataset);

}  // namespace lidarscout::dataset
