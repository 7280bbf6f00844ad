// make_dem_raster, plan_dem, make_dem_block: dem's options made a request by raster::dem_request, run by
// raster::make_dem (into a temporary folder for a raster handed back whole).
#include "python/dem_array.hpp"

#include <stdlib.h>

#include <filesystem>

#include "core/error.hpp"
#include "raster/dem.hpp"

namespace lidarscout::python {
namespace {

// A folder of its own under the system's temporary folder, removed with its files at the end of scope.
struct TemporaryFolder {
    TemporaryFolder() {
        std::string pattern = (std::filesystem::temp_directory_path() / "lidarscout-dem-XXXXXX").string();
        if (!mkdtemp(pattern.data())) throw Error(pattern, std::nullopt, "cannot make a temporary folder");
        path = pattern;
    }
    ~TemporaryFolder() {
        std::error_code ec;
        std::filesystem::remove_all(path, ec);
    }
    std::filesystem::path path;
};

}  // namespace

raster::FloatRaster make_dem_raster(const dataset::Dataset& ds, raster::DemOptions options) {
    if (!options.product.empty() && !options.method.empty()) throw Error("dem: give a product or a method, not both");
    if (options.product.empty() && options.method.empty()) options.product = "dtm";
    if (!options.product.empty() && raster::products_from_names(options.product).size() != 1) {
        throw Error("dem: give one product (it is '" + options.product + "')");
    }
    const TemporaryFolder folder;
    options.output = (folder.path / "dem.tif").string();
    const raster::DemResult result = raster::make_dem(ds, raster::dem_request(options));
    return raster::read_float_raster(result.outputs.at(0));
}

raster::DemPlan plan_dem(const dataset::Dataset& ds, const raster::DemOptions& options, int count) {
    return raster::dem_plan(ds, raster::dem_request(options), count);
}

DemBlock make_dem_block(const dataset::Dataset& ds, raster::DemOptions options, int index, int count,
                        const std::string& output) {
    options.output = output;
    options.block = std::to_string(index) + "/" + std::to_string(count);
    const raster::DemRequest request = raster::dem_request(options);
    DemBlock block{raster::make_dem(ds, request), {}};
    for (const raster::Product p : request.products) block.names.emplace_back(raster::product_name(p));
    if (request.products.empty()) block.names.emplace_back("dem");
    return block;
}

}  // namespace lidarscout::python
