// DemGrid: lattice geometry, georeferencing in the frame's units, flipped block writes.
#include "raster/dem_grid.hpp"

#include <algorithm>
#include <cmath>
#include <vector>

#include "core/error.hpp"
#include "dataset/dataset.hpp"
#include "geo/projection.hpp"
#include "las/crs.hpp"

namespace lidarscout::raster {

int DemGrid::block_width(int ix) const { return std::min(block, width - ix * block); }
int DemGrid::block_height(int iy) const { return std::min(block, height - iy * block); }

DemGrid::Window DemGrid::window() const {
    const BlockRange b = selected_blocks();
    const int col1 = std::min(width, (b.x1 + 1) * block), south = b.y0 * block;
    const int north = std::min(height, (b.y1 + 1) * block);
    return {b.x0 * block, height - north, col1 - b.x0 * block, north - south};
}

DemGrid make_dem_grid(const Area& area, double texel_m, int block) {
    if (!(texel_m > 0 && std::isfinite(texel_m))) throw Error::in_stage("dem", "the texel size must be positive");
    if (!(area.min_x <= area.max_x && area.min_y <= area.max_y)) throw Error::in_stage("dem", "the area is empty");
    DemGrid g;
    g.texel_m = texel_m;
    g.block = block;
    g.origin_x = std::floor(area.min_x / texel_m) * texel_m;
    g.origin_y = std::floor(area.min_y / texel_m) * texel_m;
    const double w = std::floor((area.max_x - g.origin_x) / texel_m) + 1;
    const double h = std::floor((area.max_y - g.origin_y) / texel_m) + 1;
    if (!(w < 2e9 && h < 2e9)) throw Error::in_stage("dem", "the raster would have more than 2^31 texels per side");
    g.width = static_cast<int>(w);
    g.height = static_cast<int>(h);
    return g;
}

Area dataset_area(const dataset::Dataset& ds) {
    if (ds.bounds_m.empty()) throw Error::in_stage("dem", "the dataset has no points");
    return {ds.bounds_m.min_x, ds.bounds_m.min_y, ds.bounds_m.max_x, ds.bounds_m.max_y};
}

RasterGeometry raster_geometry(const DemGrid& grid, const dataset::Frame& frame) {
    RasterGeometry g;
    const double f = frame.xy_to_metres;
    const DemGrid::Window w = grid.window();  // the whole grid's corner exactly when it starts there
    g.west = (w.col == 0 ? grid.origin_x : grid.origin_x + w.col * grid.texel_m) / f;
    g.north = (grid.origin_y + (grid.height - w.row) * grid.texel_m) / f;
    g.pixel_x = g.pixel_y = grid.texel_m / f;
    g.width = w.width;
    g.height = w.height;
    if (!frame.crs.empty()) g.crs_wkt = geo::crs_info(frame.crs).wkt;
    return g;
}

std::string height_unit(const dataset::Frame& frame) { return linear_unit_name(frame.z_to_metres); }

std::string linear_unit_name(double f) {
    if (std::abs(f - 1.0) < 1e-12) return "metre";
    if (std::abs(f - las::kFootMetres) < 1e-12) return "foot";
    if (std::abs(f - las::kUsSurveyFootMetres) < 1e-12) return "US survey foot";
    return "";
}

namespace {

template <typename T>
void write_flipped(BlockRaster& raster, const DemGrid& grid, int band, int ix, int iy, std::span<const T> values) {
    const int w = grid.block_width(ix), h = grid.block_height(iy);
    std::vector<T> rows(static_cast<std::size_t>(w) * h);
    for (int r = 0; r < h; ++r) {  // r counts from the north, j = h - 1 - r from the south
        const T* src = values.data() + static_cast<std::size_t>(h - 1 - r) * grid.block;
        std::copy(src, src + w, rows.begin() + static_cast<std::ptrdiff_t>(r) * w);
    }
    const DemGrid::Window window = grid.window();
    const int top = grid.height - (iy * grid.block + h);
    raster.write(band, ix * grid.block - window.col, top - window.row, w, h, std::span<const T>(rows));
}

}  // namespace

void write_block(BlockRaster& raster, const DemGrid& grid, int band, int ix, int iy, std::span<const float> values) {
    write_flipped(raster, grid, band, ix, iy, values);
}

void write_block(BlockRaster& raster, const DemGrid& grid, int band, int ix, int iy,
                 std::span<const std::uint8_t> values) {
    write_flipped(raster, grid, band, ix, iy, values);
}

}  // namespace lidarscout::raster
