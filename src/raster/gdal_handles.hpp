// Small GDAL helpers of the raster stage's readers (GDAL's headers stay in src/raster): GDAL's
// messages kept off stderr while in scope (its errors are read back through last_gdal_error), and
// an opened dataset closed at the end of its scope.
#pragma once

#include <cpl_error.h>
#include <gdal_priv.h>

namespace lidarscout::raster {

struct QuietGdal {
    QuietGdal() { CPLPushErrorHandler(CPLQuietErrorHandler); }
    ~QuietGdal() { CPLPopErrorHandler(); }
};

struct OpenRaster {
    GDALDataset* dataset = nullptr;
    ~OpenRaster() {
        if (dataset) GDALClose(dataset);
    }
};

}  // namespace lidarscout::raster
