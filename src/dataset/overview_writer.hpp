// Writing a catalog's overview sidecar (its layout: dataset/overview_sidecar.hpp): every tile's
// metadata bytes and chunk points, the tiles along a Hilbert curve, through a temporary name.
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>
#include <string>

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

// The index of (x, y) along a Hilbert curve over a 2^16 x 2^16 grid (x, y below 2^16).
std::uint64_t hilbert_index(std::uint32_t x, std::uint32_t y);

}  // namespace lidarscout::dataset
