// A shaded-relief picture of a DEM with GDAL's DEM processing (the `gdaldem hillshade` of
// gdal-bin): sun from the north-west at 45 degrees, heights and positions in the same unit
// (true of the DEMs we write: both in the CRS's unit), edges computed, nodata transparent-black.
#pragma once

#include <string>

namespace lidarscout::raster {

// Reads the DEM at `dem_path` and writes the hillshade to `png_path` (a temporary name renamed
// when complete). Throws lidarscout::Error naming the file that failed.
void write_hillshade(const std::string& dem_path, const std::string& png_path);

}  // namespace lidarscout::raster
