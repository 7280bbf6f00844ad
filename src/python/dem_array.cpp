// make_dem_raster: the request as `dem` builds it for a product or a method, made in a temporary folder.
#include "python/dem_array.hpp"

#include <stdlib.h>

#include <algorithm>
#include <filesystem>
#include <thread>

#include "core/error.hpp"
#include "raster/dem.hpp"

namespace lidarscout::python {
namespace {

raster::DemRequest dem_request(const DemQuery& q, const std::string& output) {
    raster::DemRequest r;
    r.output = output;
    r.texel_m = q.texel;
    if (q.bounds) r.area = raster::Area{(*q.bounds)[0], (*q.bounds)[1], (*q.bounds)[2], (*q.bounds)[3]};
    r.threads = q.threads ? q.threads : std::max(1u, std::thread::hardware_concurrency());
    if (!q.product.empty()) {
        if (!q.method.empty()) throw Error("dem: give a product or a method, not both");
        r.products = raster::products_from_names(q.product);
        if (r.products.size() != 1) throw Error("dem: give one product (it is '" + q.product + "')");
        if (!q.classes.empty()) r.product_options.dtm_classes = PointFilter::parse(q.classes, "", "");
        r.product_options.classes_given = !q.classes.empty();
        return r;
    }
    r.method = raster::dem_method_from_name(q.method.empty() ? "mean" : q.method, raster::DemSource::Full);
    r.filter = PointFilter::parse(q.classes, "", "");
    return r;
}

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

raster::FloatRaster make_dem_raster(const dataset::Dataset& ds, const DemQuery& query) {
    const TemporaryFolder folder;
    const raster::DemRequest request = dem_request(query, (folder.path / "dem.tif").string());
    const raster::DemResult result = raster::make_dem(ds, request);
    return raster::read_float_raster(result.outputs.at(0));
}

}  // namespace lidarscout::python
