// The lattice of a DEM in the dataset's frame (metres): texel_m squares from a south-west
// corner that is a multiple of the texel size, cut into blocks of block x block texels that
// are made (and freed) one at a time. Block (ix, iy) counts from the south-west; the raster
// file counts rows from the north, so blocks are flipped on the way out (write_block). A grid may
// select a rectangle of its blocks (`dem --block`, dem_blocks.hpp): only those are made, and the
// raster file is that rectangle, placed on the whole grid's lattice.
#pragma once

#include <algorithm>
#include <cstdint>
#include <optional>
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

// Blocks (ix, iy) from x0, y0 to x1, y1 inclusive; empty when x1 < x0 or y1 < y0.
struct BlockRange {
    int x0 = 0, y0 = 0, x1 = -1, y1 = -1;
    bool empty() const { return x1 < x0 || y1 < y0; }
    bool contains(lidarscout::CellKey c) const { return c.ix >= x0 && c.ix <= x1 && c.iy >= y0 && c.iy <= y1; }
    bool contains(const BlockRange& r) const {
        return contains(lidarscout::CellKey{r.x0, r.y0}) && contains(lidarscout::CellKey{r.x1, r.y1});
    }
    BlockRange intersection(const BlockRange& r) const {
        return {std::max(x0, r.x0), std::max(y0, r.y0), std::min(x1, r.x1), std::min(y1, r.y1)};
    }
    std::int64_t count() const { return empty() ? 0 : std::int64_t(x1 - x0 + 1) * (y1 - y0 + 1); }
    bool operator==(const BlockRange&) const = default;
};

struct DemGrid {
    double origin_x = 0, origin_y = 0;  // south-west corner, metres
    double texel_m = 1;
    int width = 0, height = 0;          // texels
    int block = 512;                    // texels per block side
    std::optional<BlockRange> selection;  // the blocks made and written (empty: every block)

    int blocks_x() const { return (width + block - 1) / block; }
    int blocks_y() const { return (height + block - 1) / block; }
    // The lattice of blocks as recon sees patches (no padding).
    recon::PatchSpec block_spec() const { return {texel_m, block, 0}; }
    // The block's texels inside the raster (edge blocks are partial).
    int block_width(int ix) const;
    int block_height(int iy) const;
    BlockRange all_blocks() const { return {0, 0, blocks_x() - 1, blocks_y() - 1}; }
    BlockRange selected_blocks() const { return selection ? *selection : all_blocks(); }
    // The texels of the selected blocks in the raster file's terms: first column, first row (from
    // the north), width and height.
    struct Window {
        int col = 0, row = 0, width = 0, height = 0;
    };
    Window window() const;
};

// The grid covering `area` (points on its max edges included). Throws Error for a texel that
// is not positive, an empty area or a raster of more than 2^31 texels per side.
DemGrid make_dem_grid(const Area& area, double texel_m, int block = 512);

// The dataset's bounds as an area.
Area dataset_area(const dataset::Dataset& dataset);

// Where the grid's window (its selected blocks) lies in the frame's CRS, in its native units (feet
// stay feet), with its WKT.
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
