// What a camera sees, at the granularity the viewer schedules work: whether a box (a patch's
// or a tile's) can be on screen (frustum test of its 8 corners), how much of the image it
// covers, and from that the visible patches of the grid and the tiles worth decoding at full
// resolution within a memory budget.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "dataset/dataset.hpp"
#include "core/patch_grid.hpp"
#include "render/camera.hpp"

namespace lidarscout::viewer {

// False only when the whole box is certainly off screen: all 8 corners outside one plane of
// the view frustum (left, right, top, bottom, near, far).
bool box_in_view(const render::Camera& camera, const dataset::Bounds& box);

// The fraction of the image covered by the screen-space bounding rectangle of the box's
// projection, clipped to the image (0..1); 1 when the box reaches behind the near plane while
// in view (the camera is in or next to it); 0 when not in view.
double screen_fraction(const render::Camera& camera, const dataset::Bounds& box);

// Distance from the camera to the nearest point of the box (0 inside).
double distance_to(const render::Camera& camera, const dataset::Bounds& box);

// The box of grid cell `cell` between heights z_min and z_max.
dataset::Bounds cell_box(const lidarscout::PatchGrid& grid, lidarscout::CellKey cell, double z_min, double z_max);

// The grid's non-empty cells whose box (heights z_min..z_max, e.g. the dataset's range) is in
// view, sorted.
std::vector<lidarscout::CellKey> visible_cells(const lidarscout::PatchGrid& grid, const render::Camera& camera,
                                            double z_min, double z_max);

struct FullResOptions {
    double min_screen_fraction = 1.0 / 8;  // a tile covering more of the image is decoded
    std::size_t few_tiles = 4;             // when at most this many tiles are visible, all are decoded
    std::uint64_t memory_budget = 0;       // bytes of decoded points at most (0 = nothing)
};

struct FullResChoice {
    std::vector<std::uint32_t> tiles;  // indices into dataset.tiles, nearest first
    std::uint64_t bytes = 0;           // their decoded size (tile_point_set_bytes)
    std::size_t wanted = 0;            // tiles that qualified before the budget
    std::size_t over_budget = 0;       // qualified tiles left out by the budget
};

// The visible tiles that qualify (large on screen, or all when few are visible), nearest to
// the camera first, each taken while it fits in what is left of the budget.
FullResChoice choose_full_res_tiles(const dataset::Dataset& dataset, const render::Camera& camera,
                                    const FullResOptions& options);

}  // namespace lidarscout::viewer
