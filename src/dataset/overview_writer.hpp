// Writing a catalog's overview sidecar (its layout: dataset/overview_sidecar.hpp): every tile's
// metadata bytes and chunk points, the tiles along a Hilbert curve, through a temporary name.
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "dataset/dataset.hpp"

namespace lidarscout::dataset {

struct OverviewWriteResult {
    std::size_t tiles = 0;     // in the table (placed from the sidecar when opened)
    std::size_t held = 0;      // of them, the tiles whose chunk points it holds
    std::size_t left_out = 0;  // tiles it cannot place (their metadata is not what read_tile reads from
                               // its bytes, e.g. a shifted COPC tile): read themselves when opened
    std::uint64_t points = 0;
    std::uint64_t bytes = 0;
};

// Writes the sidecar of `dataset` to `output` (through a temporary name, never over `protect`);
// ids[i] is the catalog item id of dataset.tiles[i]. Throws lidarscout::Error when it cannot be written.
OverviewWriteResult write_overview(const Dataset& dataset, std::span<const std::string> ids,
                                   const std::string& output, const std::string& protect = {});
// The same with each tile's chunk points given, not read: records[i] are dataset.tiles[i]'s raw records (its
// own format, in chunk_point_locations order; empty: the sidecar holds none of it), taken (moved from). What a
// viewer read already (viewer/overview_cache.hpp): a remote tile's metadata bytes come from the edges its
// open fetched, so the write asks its server for nothing more where those hold them.
OverviewWriteResult write_overview(const Dataset& dataset, std::span<const std::string> ids,
                                   std::span<std::vector<std::uint8_t>> records, const std::string& output);

// The index of (x, y) along a Hilbert curve over a 2^16 x 2^16 grid (x, y below 2^16).
std::uint64_t hilbert_index(std::uint32_t x, std::uint32_t y);

}  // namespace lidarscout::dataset
