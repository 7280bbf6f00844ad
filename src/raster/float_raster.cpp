// read_float_raster through GDAL.
#include "raster/float_raster.hpp"

#include "core/error.hpp"
#include "raster/block_raster.hpp"
#include "raster/gdal_handles.hpp"

namespace lidarscout::raster {

FloatRaster read_float_raster(const std::string& path) {
    GDALAllRegister();
    const QuietGdal quiet;
    const OpenRaster in{static_cast<GDALDataset*>(GDALOpen(path.c_str(), GA_ReadOnly))};
    if (!in.dataset) throw Error(path, std::nullopt, "cannot open the raster: " + last_gdal_error());
    FloatRaster r;
    r.width = in.dataset->GetRasterXSize(), r.height = in.dataset->GetRasterYSize();
    if (in.dataset->GetGeoTransform(r.geotransform.data()) != CE_None) {
        throw Error(path, std::nullopt, "the raster has no geotransform");
    }
    GDALRasterBand* band = in.dataset->GetRasterBand(1);
    if (!band) throw Error(path, std::nullopt, "the raster has no band");
    int has_nodata = 0;
    const double nodata = band->GetNoDataValue(&has_nodata);
    if (has_nodata) r.nodata = nodata;
    r.values.resize(static_cast<std::size_t>(r.width) * r.height);
    if (band->RasterIO(GF_Read, 0, 0, r.width, r.height, r.values.data(), r.width, r.height, GDT_Float32, 0, 0) !=
        CE_None) {
        throw Error(path, std::nullopt, "cannot read the raster: " + last_gdal_error());
    }
    return r;
}

}  // namespace lidarscout::raster
