// A georeferenced raster made block by block and delivered as a Cloud-Optimized GeoTIFF:
// blocks are written (from any thread, in any order) into a scratch tiled GeoTIFF beside the
// target, and finish() copies it with GDAL's COG driver (tiled 512 x 512, DEFLATE level 1 with
// a predictor, overviews) to a temporary name, handed to an output set that renames it with the
// others when all are complete (io/output_group.hpp). The
// scratch file is sparse (blocks never written read as nodata) and is removed in any case, so
// memory stays bounded by GDAL's block cache whatever the raster's size. Every GDAL call of
// the raster writers is in block_raster.cpp and hillshade.cpp.
#pragma once

#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <span>
#include <string>

namespace lidarscout::io {
class OutputGroup;
}

namespace lidarscout::raster {

// Where the raster lies, in the CRS's native units: the north-west corner of the top-left
// pixel and the pixel size; rows run from north to south.
struct RasterGeometry {
    double west = 0, north = 0;
    double pixel_x = 1, pixel_y = 1;  // positive
    int width = 0, height = 0;
    std::string crs_wkt;  // empty: no CRS recorded
};

enum class PixelType { Float32, Byte };

struct RasterLayout {
    int bands = 1;
    PixelType type = PixelType::Float32;
    std::optional<double> nodata;     // recorded in the file
    bool alpha_last = false;          // the last band is an alpha band (an RGBA image)
    std::string unit;                 // band unit ("metre", "US survey foot"), empty for none
    std::string description;          // band description of band 1, e.g. "elevation"
};

// Called with the fraction done (0..1) of the COG copy.
using RasterProgressFn = std::function<void(double)>;

class BlockRaster {
public:
    // Throws lidarscout::Error (naming `target`) when the scratch file cannot be created.
    BlockRaster(std::string target, const RasterGeometry& geometry, const RasterLayout& layout);
    ~BlockRaster();  // removes the scratch file (and, without finish(), writes nothing)
    BlockRaster(const BlockRaster&) = delete;
    BlockRaster& operator=(const BlockRaster&) = delete;

    const RasterGeometry& geometry() const { return geometry_; }

    // Writes a w x h window at column x0, row y0 (rows north first) of band `band` (1-based).
    // Thread-safe.
    void write(int band, int x0, int y0, int w, int h, std::span<const float> values);
    void write(int band, int x0, int y0, int w, int h, std::span<const std::uint8_t> values);

    // Writes the COG under a temporary name and hands it to `outputs`, whose commit() renames it
    // to the target. `threads` compress in parallel.
    void finish(unsigned threads, io::OutputGroup& outputs, const RasterProgressFn& progress = {});

private:
    struct State;
    void write_raw(int band, int x0, int y0, int w, int h, const void* data, std::size_t count, PixelType type);

    std::string target_;
    RasterGeometry geometry_;
    RasterLayout layout_;
    std::unique_ptr<State> state_;
};

// GDAL's wording of the last error, for messages ("" when none).
std::string last_gdal_error();

}  // namespace lidarscout::raster
