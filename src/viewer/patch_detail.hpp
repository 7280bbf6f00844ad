// What full-resolution points teach the heightmaps: per patch texel, the mean height and mean
// colour of every decoded point that fell in it, gathered from each tile before its points are
// released, and laid over the patch's interpolated (or network) heightmap so that medium zoom
// keeps the detail once the points are gone.
#pragma once

#include <cstdint>
#include <span>
#include <unordered_map>
#include <vector>

#include "core/patch_grid.hpp"
#include "viewer/patch_heightmap.hpp"
#include "viewer/point_sets.hpp"

namespace lidarscout::viewer {

// Means per texel of one patch (the grid cell's 64 x 64 texels, row 0 = south).
struct PatchDetail {
    double origin_x = 0, origin_y = 0;   // the cell's min corner, world metres
    double texel_m = 10;
    int size = 64;
    std::vector<float> height;           // mean height, metres (NaN where no point fell)
    std::vector<std::uint32_t> count;    // points behind each mean
    std::vector<std::uint32_t> colour;   // mean colour, rgba8

    std::uint64_t bytes() const { return height.capacity() * 4 + count.capacity() * 4 + colour.capacity() * 4; }
};

using PatchDetails = std::unordered_map<lidarscout::CellKey, PatchDetail, lidarscout::CellKeyHash>;

// The detail of every grid cell the points of `set` (one tile) fall in, `size` texels per side.
PatchDetails tile_detail(const PointSet& set, const lidarscout::PatchGrid& grid, int size);

// Merges `from` into `into` (the same cell): per texel the count-weighted mean.
void merge_detail(PatchDetail& into, const PatchDetail& from);

// `base` with every texel that has detail replaced by the detail's height (and colour, when
// the base has a texture).
PatchHeightmap overlay_detail(const PatchHeightmap& base, const PatchDetail& detail);

// Lays the detail of every point of `sets` (tiles decoded whole) over the heightmaps of the cells
// they fall in, as the scheduler does once those tiles are resident: the surface under real
// points stands at their height, not at the interpolation's, so that it does not hide them.
void overlay_points(std::vector<PatchHeightmap>& heightmaps, std::span<const PointSet> sets,
                    const lidarscout::PatchGrid& grid);

}  // namespace lidarscout::viewer
