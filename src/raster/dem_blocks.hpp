// The pieces of `dem --block I/N`: the blocks of a DEM's grid (the grid of the whole dataset, or
// of --bounds) split into N rectangles of about equal point counts, estimated from the tiles'
// headers (a tile's points spread evenly over its bounds), by cutting the longer side of a
// rectangle where the two parts carry shares of the points closest to their shares of the pieces.
// Every process that opens the same tiles gets the same pieces, so N runs of `dem --block I/N`
// (on one machine or many) make rasters that mosaic into the DEM of one whole run, texel for
// texel: a block is made from every point within its reach whichever piece it is in (full_dem.hpp).
#pragma once

#include <string_view>
#include <utility>
#include <vector>

#include "raster/dem_grid.hpp"

namespace lidarscout::dataset {
struct Dataset;
}

namespace lidarscout::raster {

// "I/N" (1 <= I <= N): the piece I of N. Throws Error naming --block otherwise.
std::pair<int, int> parse_block_piece(std::string_view text);

// The N pieces, in the order of their numbers (piece I is element I - 1). Throws Error when the
// grid has fewer than N blocks.
std::vector<BlockRange> dem_block_pieces(const dataset::Dataset& dataset, const DemGrid& grid, int count);

// Points per block of the grid (slot iy * blocks_x + ix), estimated from the tiles' headers.
std::vector<double> block_point_estimates(const dataset::Dataset& dataset, const DemGrid& grid);
// The sum of those estimates over `blocks`.
double points_in(const std::vector<double>& estimates, const DemGrid& grid, const BlockRange& blocks);

}  // namespace lidarscout::raster
