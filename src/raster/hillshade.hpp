// A shaded-relief picture of a DEM with GDAL's DEM processing (the `gdaldem hillshade` of
// gdal-bin): sun from the north-west at 45 degrees, heights and positions in the same unit
// (true of the DEMs we write: both in the CRS's unit), edges computed, nodata transparent-black.
// Georeferenced like the DEM: a `.tif` is a GeoTIFF (deflate, tiled) with the DEM's CRS and
// geotransform; a `.png` gets its world file (`.pgw`) and a `.png.aux.xml` holding the CRS.
#pragma once

#include <string>

namespace lidarscout::io {
class OutputGroup;
}

namespace lidarscout::raster {

// Reads the DEM `dem_path` (where `outputs` holds it, when it is one of its files) and writes the
// hillshade to `path` (.tif/.tiff or .png), and a PNG's sidecars, under temporary names that
// `outputs` renames with the rest of the set. Throws lidarscout::Error naming the file that failed,
// or for another extension.
void write_hillshade(const std::string& dem_path, const std::string& path, io::OutputGroup& outputs);

// True for a .png hillshade, false for .tif/.tiff; throws lidarscout::Error for another extension
// (make_dem asks before any work).
bool hillshade_is_png(const std::string& path);

}  // namespace lidarscout::raster
