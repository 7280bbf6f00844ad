// A DEM or a height product of a dataset for Python: made by raster::make_dem (what `dem` makes) into
// a temporary folder, read back whole (raster/float_raster.hpp) and the folder removed.
#pragma once

#include <array>
#include <optional>
#include <string>

#include "dataset/dataset.hpp"
#include "raster/float_raster.hpp"

namespace lidarscout::python {

struct DemQuery {
    double texel = 1.0;
    std::string product = "dtm";  // one of `dem --product`'s; empty: one DEM by `method`
    std::string method;           // `dem --method` (full points); empty: mean
    std::optional<std::array<double, 4>> bounds;  // in the CRS's units; empty: the dataset's
    std::string classes;  // `--classes`: the dtm's ground classes, or the DEM's filter
    unsigned threads = 0;  // 0: every core
};

// Throws Error as `dem` does (a bad product, method, texel or area; a raster over the memory budget).
raster::FloatRaster make_dem_raster(const dataset::Dataset& ds, const DemQuery& query);

}  // namespace lidarscout::python
