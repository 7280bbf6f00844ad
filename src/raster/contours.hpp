// Contour lines of a height raster with GDAL's contour generator (GDALContourGenerateEx, the
// `gdal_contour` of gdal-bin): every INTERVAL in the raster's height unit, nodata left out, as a
// GeoPackage of line strings (layer "contours", the raster's CRS) with their height in the
// attribute "elevation", written through a temporary name.
#pragma once

#include <cstdint>
#include <functional>
#include <string>

namespace lidarscout::io {
class OutputGroup;
}

namespace lidarscout::raster {

// The GeoPackage beside a height raster: out.tif -> out_contours.gpkg.
std::string contours_path(const std::string& raster_path);

// Writes the contours of band 1 of `raster_path` (read where `outputs` holds it, when it is one of its
// files; nodata `nodata`) every `interval` to `gpkg_path`, under a temporary name that `outputs`
// renames with the rest of the set; returns how many lines. Throws lidarscout::Error naming the file
// that failed, for an interval that is not a positive number, and when there is no line (the
// heights' range said, nothing written). `progress` gets the fraction done (0..1).
std::uint64_t write_contours(const std::string& raster_path, const std::string& gpkg_path, double interval,
                             double nodata, io::OutputGroup& outputs, const std::function<void(double)>& progress = {});

}  // namespace lidarscout::raster
