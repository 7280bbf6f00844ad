// The lattice of a DEM in the dataset's frame (metres): texel_m squares from a south-west
// corner that is a multiple of the texel size, cut into blocks of block x block texels that
// are made (and freed) one at a time. Block (ix, iy) counts from the south-west; the raster
// file counts rows from the north, so blocks are flipped on the way out (write_block).
#pragma once

#include <span>
#include <string>

#include "raster/block_raster.hpp"
#include "recon/patch_space.hpp"

namespace lidarscout::dataset {
struct Dataset;
struct Frame;
}

namespace lidarscout::raster {

// An area in the dataset's frame, metres.
struct Area {
    double min_x = 0, min_y = 0, max_x = 0, max_y = 0;
};

struct DemGrid {
    double origin_x = 0, origin_y = 0;  // south-west corner, metres
    double texel_m = 1;
    int width = 0, height = 0;          // texels
    int block = 512;                    // texels per block side

    int blocks_x() const { return (width + block - 1) / block; }
    int blocks_y() const { return (height + block - 1) / block; }
    // The lattice of blocks as recon sees patches (no padding).
    recon::PatchSpec block_spec() const { return {texel_m, block, 0}; }
    // The block's texels inside the raster (edge blocks are partial).
    int block_width(int ix) const;
    int block_height(int iy) const;
};

// The grid covering `area` (points on its max edges included). Throws Error for a texel that
// is not positive, an empty area or a raster of more than 2^31 texels per side.
DemGrid make_dem_grid(const Area& area, double texel_m, int block = 512);

// The dataset's bounds as an area.
Area dataset_area(const dataset::Dataset& dataset);

// Where the grid lies in the frame's CRS, in its native units (feet stay feet), with its WKT.
RasterGeometry raster_geometry(const DemGrid& grid, const dataset::Frame& frame);
// The band unit of heights in the frame's vertical unit: "metre", "foot", "US survey foot" or "".
std::string height_unit(const dataset::Frame& frame);
// The name of a linear unit from its factor to metres ("metre", "foot", "US survey foot"; "" for
// another).
std::string linear_unit_name(double to_metres);

// Writes block (ix, iy), given as block x block values with rows from the south (the layout of
// recon's images), into band `band` of `raster`, flipped to rows from the north.
void write_block(BlockRaster& raster, const DemGrid& grid, int band, int ix, int iy, std::span<const float> values);
void write_block(BlockRaster& raster, const DemGrid& grid, int band, int ix, int iy,
                 std::span<const std::uint8_t> values);

}  // namespace lidarscout::raster
