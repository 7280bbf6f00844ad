// DEMs from every point (`lidarscout dem --from full`): tiles are streamed one at a time in
// south-to-north order (LAZ chunks decoded in parallel), each point the filter keeps is
// given to the blocks within its reach (block_gridders.hpp: its texel for mean/min/max — the
// same gridding as `eval`'s ground truth, so `--method mean` equals it texel by texel — the
// texels within the radius for idw, the blocks whose margin holds it for tin), and a block is
// finished — gridded, written, freed — as soon as the last tile that reaches it is done.
// Memory is therefore the blocks under the tiles in flight, not the raster. A point outside its
// tile's header bounds (beyond a texel; its block may already be written) and a LAZ chunk that
// cannot be decoded cost their points only, named and counted (FullDemStats::skipped).
#pragma once

#include <array>
#include <cstdint>
#include <functional>
#include <vector>

#include "core/error.hpp"
#include "core/point_filter.hpp"

#include "raster/block_gridders.hpp"
#include "raster/dem_grid.hpp"

namespace lidarscout {
class ThreadPool;
}
namespace lidarscout::dataset {
struct Dataset;
}

namespace lidarscout::raster {

struct FullDemOptions {
    GridderSpec gridder;  // mean/min/max, idw or tin (its rgb flag follows DemOutputs::rgb)
    PointFilter filter;  // points it does not keep are left out
    float nodata = -9999.0f;
    // Called after each batch of points: (points done, points total).
    std::function<void(std::uint64_t, std::uint64_t)> progress;
};

// Where the finished blocks go: heights (band 1, the frame's vertical unit) and, when `rgb` is
// set, colour (bands 1-3) with alpha (band 4, 255 where a height is).
struct DemOutputs {
    BlockRaster* heights = nullptr;
    BlockRaster* rgb = nullptr;
    double z_to_metres = 1.0;  // heights are written in metres / z_to_metres
};

struct FullDemStats {
    std::uint64_t points_read = 0, points_used = 0;
    // LAZ chunks (or whole tiles) that could not be decoded: left out, the DEM made without them.
    std::vector<ErrorRecord> skipped;
    std::uint64_t points_skipped = 0;
    std::size_t blocks_written = 0;
    std::size_t peak_blocks = 0;  // blocks held at once
};

// Bytes grid_full_dem may hold at once, estimated before anything is allocated: the blocks of a
// band as wide as the raster and as tall as the tallest tile's blocks plus one (blocks finish when
// the row of tiles above them is done), at the gridder's bytes per texel, and a count per block.
std::uint64_t full_dem_peak_bytes(const dataset::Dataset& dataset, const DemGrid& grid, const GridderSpec& gridder,
                                  bool rgb);

FullDemStats grid_full_dem(const dataset::Dataset& dataset, const DemGrid& grid, const FullDemOptions& options,
                           const DemOutputs& outputs, ThreadPool& pool);

}  // namespace lidarscout::raster
