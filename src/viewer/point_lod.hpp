// Level of detail for full-resolution points: a decoded tile is cut into square blocks of a
// world-aligned grid and each block's points are reordered coarse to fine (SimLOD-style nested
// sampling on a quadtree of cells): level k keeps one point per cell of side block_m / 2^k (the
// highest, what a view from above sees first), so
// drawing level k is drawing a prefix of the block's points, and the last level is every point.
// A frame draws, per block, the prefix whose spacing matches the screen (about one point per
// pixel at the block's nearest distance); a released tile keeps a short prefix of each block
// (its coarse levels), so visited regions stay sharper than their heightmaps.
#pragma once

#include <array>
#include <cstdint>
#include <memory>
#include <span>
#include <vector>

#include "core/thread_pool.hpp"
#include "dataset/dataset.hpp"
#include "render/camera.hpp"
#include "render/point_batch.hpp"
#include "viewer/point_sets.hpp"

namespace lidarscout::viewer {

// Levels 0..16 halve the cell side each time (16 bits per axis in the block's quadtree code);
// level 17 holds the points that share their finest cell with an earlier point.
inline constexpr std::size_t kLodLevels = 18;

struct LodBlock {
    PointSet points;                                 // coarse to fine; origin = the tile's
    std::array<std::uint32_t, kLodLevels> level_end{};  // level k = points[0, level_end[k])
    std::array<std::uint64_t, kLodLevels> level_key{};  // render cache key of each prefix (0: none)
    double size_m = 80;                              // the block's side
    dataset::Bounds bounds;                          // of its points, world metres
    std::uint32_t tile = 0;
    std::size_t levels = kLodLevels;                 // levels held (fewer in a coarse copy)

    // Side of the cells of level k (0 for the last level: duplicates of the finest cells).
    double spacing(std::size_t level) const;
    // Its points and itself; its class counts' few dozen bytes are left out, as in the residency's
    // estimate of a tile (tile_point_set_bytes), which a larger figure would overrun at tiny budgets.
    std::uint64_t bytes() const { return points.points.capacity() * sizeof(render::PointAttr) + sizeof(LodBlock); }
    // The points of levels 0..level (clamped to the levels held), their spacing that level's
    // cells (at least the tile's mean spacing, which the last level has).
    render::PointBatch prefix(std::size_t level) const;
};

using LodBlocks = std::vector<std::shared_ptr<const LodBlock>>;

// The quadtree code of a block-local position (0..1 on each axis, clamped): 16 bits per axis
// interleaved, x in the even bits.
std::uint32_t quadtree_code(double u, double v);
// The level at which the point with code `code` is the first of its cell, given the previous
// code in sorted order (none for the block's first point: level 0).
std::size_t first_level(std::uint32_t code, std::uint32_t previous);

// Cuts `tile` (one tile's decoded points) into blocks of side `block_m` on the world grid and
// orders each coarse to fine; blocks are built in parallel on `pool`.
LodBlocks build_lod_blocks(const PointSet& tile, std::uint32_t tile_index, double block_m, ThreadPool& pool);

// The finest level of `block` whose spacing is at least `spacing_m` (at least level 0).
std::size_t coarse_level(const LodBlock& block, double spacing_m);
// The coarse copy of a block: the levels whose spacing is at least `spacing_m` (at least
// level 0). Keeps the cache keys of those prefixes.
std::shared_ptr<const LodBlock> coarse_copy(const LodBlock& block, double spacing_m);
std::uint64_t lod_bytes(const LodBlocks& blocks);
std::uint64_t lod_points(const LodBlocks& blocks);

// Metres one pixel spans at `distance` from the camera (at the image centre).
double pixel_footprint(const render::Camera& camera, double distance);

// The level of `block` to draw at `camera`: the coarsest whose spacing is at most
// `spacing_px` pixels at the block's nearest distance (`spacing_px` <= 0: the finest held).
std::size_t level_for(const LodBlock& block, const render::Camera& camera, double spacing_px);

// The prefixes to draw for `camera`: the blocks in view, each at level_for.
std::vector<render::PointBatch> lod_batches(const LodBlocks& blocks, const render::Camera& camera, double spacing_px);

}  // namespace lidarscout::viewer
