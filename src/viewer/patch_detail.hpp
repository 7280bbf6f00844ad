// What full-resolution points teach the heightmaps: per patch texel, the mean height and mean
// colour of every decoded point that fell in it (and apart of its ground and water points),
// gathered from each tile before its points are released, and laid over the patch's
// interpolated (or network) heightmap so that medium zoom keeps the detail once the points are
// gone, and so that a ground filter turns the surface into bare earth as tiles are read.
#pragma once

#include <cstdint>
#include <span>
#include <unordered_map>
#include <vector>

#include "core/patch_grid.hpp"
#include "viewer/patch_heightmap.hpp"
#include "viewer/point_sets.hpp"

namespace lidarscout::viewer {

// Means per texel of one set of points over one patch (the grid cell's texels, row 0 = south).
struct DetailLayer {
    std::vector<float> height;           // mean height, metres (NaN where no point fell)
    std::vector<std::uint32_t> count;    // points behind each mean
    std::vector<std::uint32_t> colour;   // mean colour, rgba8

    bool empty() const { return count.empty(); }
    std::uint64_t bytes() const { return height.capacity() * 4 + count.capacity() * 4 + colour.capacity() * 4; }
};

// The detail of one patch: every point, and apart the ground (class 2) and water (class 9) points
// a bare-earth filter shows (each layer empty when the patch's tiles have none of them).
struct PatchDetail {
    double origin_x = 0, origin_y = 0;   // the cell's min corner, world metres
    double texel_m = 10;
    int size = 64;
    DetailLayer all, ground, water;

    std::uint64_t bytes() const { return all.bytes() + ground.bytes() + water.bytes(); }
};

// Detail layers a patch may hold per texel and the bytes of each texel of one (height, count and colour).
inline constexpr int kDetailLayers = 3;
inline constexpr std::uint64_t kDetailLayerTexelBytes = 12;

using PatchDetails = std::unordered_map<lidarscout::CellKey, PatchDetail, lidarscout::CellKeyHash>;

// The detail of every grid cell the points of `set` (one tile) fall in, `size` texels per side.
PatchDetails tile_detail(const PointSet& set, const lidarscout::PatchGrid& grid, int size);

// Merges `from` into `into` (the same cell): per texel the count-weighted mean.
void merge_detail(PatchDetail& into, const PatchDetail& from);

// `base` with every texel that has detail replaced by the detail's height (and colour, when
// the base has a texture). For a bare-earth surface (Surface::Ground ...): where the surface's
// points fell, their mean; where only other points fell (under a roof, a dense canopy), the
// surface interpolated between those texels (hole_fill); where no full-resolution point fell
// yet, the base, marked as standing for every point (colour alpha kOverviewAlpha: drawn tinted,
// PatchHeightmap::view). The result always has colours then (grey for an untextured base).
PatchHeightmap overlay_detail(const PatchHeightmap& base, const PatchDetail& detail, Surface surface = Surface::All);

// Lays the detail of every point of `sets` (tiles decoded whole) over the heightmaps of the cells
// they fall in, as the scheduler does once those tiles are resident: the surface under real
// points stands at their height, not at the interpolation's, so that it does not hide them.
void overlay_points(std::vector<PatchHeightmap>& heightmaps, std::span<const PointSet> sets,
                    const lidarscout::PatchGrid& grid, Surface surface = Surface::All);

}  // namespace lidarscout::viewer
