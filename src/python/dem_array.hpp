// DEMs and height products of a dataset for Python, made by raster::make_dem from dem's options
// (raster/dem_options.hpp, as `dem` turns them into a request): one whole raster made into a temporary
// folder and read back (ds.dem), the plan of `dem --plan N` (ds.dem_plan) and one piece of
// `dem --block I/N` written as `dem` writes it (ds.dem_block, what the Dask driver runs on its workers).
#pragma once

#include <string>
#include <vector>

#include "dataset/dataset.hpp"
#include "raster/dem_options.hpp"
#include "raster/float_raster.hpp"

namespace lidarscout::python {

// One raster: `options.product` (one product) or a DEM by `options.method`; with neither, the dtm.
// Its output is a temporary file. Throws Error as `dem` does (a bad product, method, texel or area; a
// raster over the memory budget), and for several products or both a product and a method.
raster::FloatRaster make_dem_raster(const dataset::Dataset& ds, raster::DemOptions options);

// `dem --plan count`: the grid and its pieces (their blocks, texels, points and memory estimates).
raster::DemPlan plan_dem(const dataset::Dataset& ds, const raster::DemOptions& options, int count);

// `dem -o output --block index/count`: the piece's rasters written (each under a temporary name, then
// renamed), a DEM or each product's (DemResult::outputs); refused before any work when its memory
// estimate exceeds options.memory.
struct DemBlock {
    raster::DemResult result;
    std::vector<std::string> names;  // of result.outputs: each product's, or "dem"
};
DemBlock make_dem_block(const dataset::Dataset& ds, raster::DemOptions options, int index, int count,
                        const std::string& output);

}  // namespace lidarscout::python
