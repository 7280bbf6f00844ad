// `dem`'s options as a user gives them (texts, numbers, what was given), turned into the DemRequest
// make_dem runs: shared by the CLI's `dem` and the Python module's `dem_plan`/`dem_block`, so that
// both refuse the same combinations with the same messages. Also the plan of `dem --plan N`: the
// grid, its N pieces (dem_blocks.hpp), the points and memory each is estimated to need.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "raster/dem.hpp"
#include "recon/ground_filter.hpp"

namespace lidarscout::raster {

struct DemOptions {
    std::string output, rgb, hillshade, model;
    double texel = 1.0;
    std::vector<double> bounds;  // xmin, ymin, xmax, ymax in the CRS's units; empty: the whole dataset
    std::string from = "full";
    std::string method;  // empty: mean (full) or linear (overview)
    std::string classes, returns, intensity;  // core/point_filter.hpp's texts
    std::optional<double> radius, power, max_edge;  // idw, idw, tin and products
    std::string product;  // empty: one DEM by `method`
    std::string ground = "classes";  // the dtm's ground: the classes, or smrf (the ground filter)
    recon::GroundFilterParams ground_params;
    std::vector<std::string> ground_options;  // the --ground-* options given
    std::optional<double> contours;  // interval, in the raster's height unit
    bool force = false;  // contours past kContourLineLimit
    std::string block;   // "I/N", empty: the whole DEM
    std::uint64_t memory = 0;  // bytes; 0: half of what the process may use
    unsigned threads = 0;      // 0: every core
};

// The request; throws Error naming the option (as `dem --OPTION`) for a value or a combination dem refuses.
DemRequest dem_request(const DemOptions& options);

// One piece of `dem --block I/N`: its blocks and texels (column, row from the north, width, height)
// of the whole grid, the points the tile headers put in it and the memory it is estimated to need.
struct DemPiece {
    int index = 0;  // I, from 1
    BlockRange blocks;
    DemGrid::Window window;
    double points = 0;
    std::uint64_t memory_estimate = 0;
};

struct DemPlan {
    DemGrid grid;
    std::int64_t blocks = 0;    // of the whole grid
    std::uint64_t points = 0;   // of every tile
    std::vector<DemPiece> pieces;
};

// The grid of `request` and its `count` pieces; throws Error when the grid has fewer blocks.
DemPlan dem_plan(const dataset::Dataset& dataset, const DemRequest& request, int count);

}  // namespace lidarscout::raster
