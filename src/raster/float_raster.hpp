// A single-band raster read back whole as float32 (a DEM or a height product this stage wrote), with
// its GDAL geotransform and nodata value: what the Python module hands out as a numpy array.
#pragma once

#include <array>
#include <optional>
#include <string>
#include <vector>

namespace lidarscout::raster {

struct FloatRaster {
    int width = 0, height = 0;
    // GDAL's: x of the west edge, x per column, 0, y of the north edge, 0, y per row (negative).
    std::array<double, 6> geotransform{};
    std::optional<double> nodata;
    std::vector<float> values;  // row by row from the north, width * height
};

// Band 1 of the raster at `path`. Throws Error (naming the file and GDAL's message) when it cannot be
// opened or read; GDAL prints nothing.
FloatRaster read_float_raster(const std::string& path);

}  // namespace lidarscout::raster
