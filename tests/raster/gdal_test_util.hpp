// Reading a raster back with GDAL in the tests (band values, geotransform, nodata, CRS), and
// running gdal-bin's tools (gdalinfo -json) as a user would.
#pragma once

#include <gdal_priv.h>
#include <ogr_spatialref.h>

#include <optional>
#include <string>
#include <vector>

#include "test_data.hpp"

namespace lidarscout::test {

struct ReadRaster {
    int width = 0, height = 0, bands = 0;
    double transform[6] = {};
    std::optional<double> nodata;
    std::vector<float> values;  // band `band`, rows from the north
    std::string crs_wkt;
    int epsg = 0;  // the horizontal EPSG code GDAL identifies, 0 when none
    float at(int row, int col) const { return values[static_cast<std::size_t>(row) * width + col]; }
};

inline ReadRaster read_raster(const std::string& path, int band = 1) {
    GDALAllRegister();
    ReadRaster r;
    GDALDataset* ds = static_cast<GDALDataset*>(GDALOpen(path.c_str(), GA_ReadOnly));
    if (!ds) return r;
    r.width = ds->GetRasterXSize();
    r.height = ds->GetRasterYSize();
    r.bands = ds->GetRasterCount();
    ds->GetGeoTransform(r.transform);
    GDALRasterBand* b = ds->GetRasterBand(band);
    int has = 0;
    const double nd = b->GetNoDataValue(&has);
    if (has) r.nodata = nd;
    r.values.resize(static_cast<std::size_t>(r.width) * r.height);
    if (b->RasterIO(GF_Read, 0, 0, r.width, r.height, r.values.data(), r.width, r.height, GDT_Float32, 0, 0) !=
        CE_None) {
        r.values.clear();
    }
    if (const OGRSpatialReference* srs = ds->GetSpatialRef()) {
        char* wkt = nullptr;
        srs->exportToWkt(&wkt);
        r.crs_wkt = wkt ? wkt : "";
        CPLFree(wkt);
        const char* code = srs->IsCompound() ? nullptr : srs->GetAuthorityCode(nullptr);
        if (srs->IsCompound()) {
            OGRSpatialReference h(*srs);
            h.StripVertical();
            code = h.GetAuthorityCode(nullptr);
            r.epsg = code ? std::atoi(code) : 0;
        } else {
            r.epsg = code ? std::atoi(code) : 0;
        }
    }
    GDALClose(ds);
    return r;
}

// `gdalinfo -json PATH` parsed (gdal-bin); an empty object when it fails.
inline nlohmann::json gdalinfo(const std::string& path) {
    std::string out;
    if (run_command("gdalinfo -json '" + path + "' 2>/dev/null", out) != 0) return nlohmann::json::object();
    return nlohmann::json::parse(out);
}

}  // namespace lidarscout::test
