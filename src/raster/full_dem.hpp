// DEMs from every point (`lidarscout dem --from full`): tiles are streamed one at a time in
// south-to-north order (LAZ chunks decoded in parallel), each point the filter keeps is
// given to the blocks within its reach (block_gridders.hpp: its texel for mean/min/max — the
// same gridding as `eval`'s ground truth, so `--method mean` equals it texel by texel — the
// texels within the radius for idw, the blocks whose margin holds it for tin), and a block is
// finished — gridded, written, freed — as soon as the last tile that reaches it is done.
// Memory is therefore the blocks under the tiles in flight, not the raster. A point outside its
// tile's header bounds (beyond a texel; its block may already be written) and a LAZ chunk that
// cannot be decoded cost their points only, named and counted (FullDemStats::skipped).
// Only the grid's selected blocks are made (DemGrid::selection, `dem --block`), from the tiles that
// reach them; each is the same, texel for texel, as in a run of every block.
// One pass can grid several layers at once (grid_full_layers: `dem --product`), each with its own
// points (filter) and gridder; a block holds one gridder per layer and is finished for all at once.
#pragma once

#include <array>
#include <cstdint>
#include <functional>
#include <span>
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

// One accumulation of a pass: the points `filter` keeps, gridded by `gridder`.
struct GridLayer {
    GridderSpec gridder;
    PointFilter filter;
};

// Given each finished block (its key) with one BlockImages per layer, in the layers' order.
using BlockWriteFn = std::function<void(CellKey block, std::vector<BlockImages>& layers)>;

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
    std::uint64_t peak_held_points = 0;  // points the blocks held at once (tin blocks; before a tile's blocks finish)
    std::vector<std::uint64_t> layer_points;  // per layer of grid_full_layers: the points it was given
};

// Bytes grid_full_dem may hold at once, estimated before anything is allocated: the blocks of a
// band as wide as the grid's selected blocks and as tall as the tallest tile's blocks plus one
// (blocks finish when the row of tiles above them is done) at the gridder's bytes per texel, the
// points the tin blocks hold (held_points_estimate) and the densest one's finishing, a count per
// block of the grid, the batches of points being read and the program itself.
std::uint64_t full_dem_peak_bytes(const dataset::Dataset& dataset, const DemGrid& grid, const GridderSpec& gridder,
                                  bool rgb);
// The same for several layers gridded in one pass.
std::uint64_t full_layers_peak_bytes(const dataset::Dataset& dataset, const DemGrid& grid,
                                     std::span<const GridLayer> layers);

// The points the tin layers' blocks may hold at once, from the tile headers' counts (spread evenly
// over their bounds): the most in a band across the selected blocks as tall as a block, its
// margins and the tallest tile (the tiles are read south to north), times the share of points that
// two or four blocks hold. 0 without a tin layer.
double held_points_estimate(const dataset::Dataset& dataset, const DemGrid& grid, std::span<const GridLayer> layers);

// Heights in metres (NaN: none) in a file's vertical unit (metres / z_to_metres), `nodata` where none.
std::vector<float> heights_in_file_units(std::span<const float> metres, double z_to_metres, float nodata);

// Every layer in one read of the points (a point goes to each layer whose filter keeps it), each
// finished block given to `write`. `progress`: (points done, points total) after each batch.
FullDemStats grid_full_layers(const dataset::Dataset& dataset, const DemGrid& grid, std::span<const GridLayer> layers,
                              const BlockWriteFn& write, ThreadPool& pool,
                              const std::function<void(std::uint64_t, std::uint64_t)>& progress = {});

FullDemStats grid_full_dem(const dataset::Dataset& dataset, const DemGrid& grid, const FullDemOptions& options,
                           const DemOutputs& outputs, ThreadPool& pool);

}  // namespace lidarscout::raster
