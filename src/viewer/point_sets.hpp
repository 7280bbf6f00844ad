// Points the point pass draws, owned by the viewer: the chunk points of a grid cell (origin =
// the cell's corner) and the full-resolution points of a tile (origin = the tile's min corner),
// each as float offsets from a double origin (render/point_batch.hpp).
#pragma once

#include <cstdint>
#include <functional>
#include <span>
#include <utility>
#include <vector>

#include "core/thread_pool.hpp"
#include "dataset/dataset.hpp"
#include "core/point_filter.hpp"
#include "core/patch_grid.hpp"
#include "dataset/point_reader.hpp"
#include "render/point_batch.hpp"

namespace lidarscout::viewer {

struct PointSet {
    double origin_x = 0, origin_y = 0, origin_z = 0;  // world metres
    std::vector<render::PointAttr> points;
    std::uint64_t cache_key = 0;  // render::PointBatch::cache_key, given to sets shared once complete
    float spacing_m = 0;          // render::PointBatch::spacing_m: a tile's mean point spacing
    // LOD blocks: their points by class, the classes present only (the Filters panel's counts).
    std::vector<std::pair<std::uint8_t, std::uint32_t>> class_counts;

    render::PointBatch batch() const { return {origin_x, origin_y, origin_z, points, cache_key, spacing_m}; }
};

// The mean spacing of a tile's points, from its header: sqrt(area of its bounds / points), metres;
// infinity for a tile without points.
double mean_point_spacing(const dataset::DatasetTile& tile);

// Batches viewing every set (the sets must outlive them).
std::vector<render::PointBatch> batches_of(std::span<const PointSet> sets);
std::uint64_t point_count(std::span<const PointSet> sets);
// Sets set.class_counts from its points.
void count_classes(PointSet& set);

// The chunk points stored in `cell` of the grid; origin = the cell's min corner at z = 0; no spacing.
PointSet cell_point_set(const lidarscout::PatchGrid& grid, lidarscout::CellKey cell);
// A grid point as drawn: its offset in its cell moved by (dx, dy) (to another origin), its z as is.
render::PointAttr chunk_point_attr(const GridPoint& point, float dx, float dy);

// The grey of surfaces without colour (as the heightmap pass draws untextured patches).
inline constexpr std::uint8_t kUncolouredGrey = 170;
// Gives every point the grey above: for surveys without colour (their points load as black),
// so that RGB mode shows them like their heightmaps.
void paint_uncoloured(std::span<PointSet> sets);
// Whether a survey counts as coloured: at least half its tiles (and one) have RGB.
bool survey_has_rgb(const dataset::Dataset& ds);

// Bytes a tile's full-resolution PointSet takes (its point count x sizeof(PointAttr)).
std::uint64_t tile_point_set_bytes(const dataset::DatasetTile& tile);

// Every point of the tile, decoded (LAZ chunks in parallel on `pool`), in metres, colour to 8
// bits by the tile's chunk points (dataset::colour_is_16bit), spacing = mean_point_spacing.
// `progress(points)` is called after each batch of decoded points. Throws lidarscout::Error when
// the tile cannot be decoded; with `skipped`, only when it cannot be opened: a LAZ chunk that
// cannot be decoded is left out and appended to it. With `filter`, only the points it keeps.
PointSet tile_point_set(const dataset::DatasetTile& tile, std::uint64_t las_stride, ThreadPool& pool,
                        const std::function<void(std::uint64_t)>& progress = {},
                        std::vector<dataset::SkippedChunk>* skipped = nullptr,
                        const PointFilter* filter = nullptr);

// A sort key for a world position (metres); lower first.
using PointOrder = std::function<double(double x, double y, double z)>;

// The same points as tile_point_set, decoded in pieces: the LAZ chunks sorted by `order` at
// their chunk points (those without one last), about `piece_points` points per piece (whole
// chunks), the pieces decoded in parallel on `pool` (each by one thread, in that order), each
// handed to `on_piece` as soon as it is decoded (origin = the tile's min corner; `on_piece` is
// called from several threads at once). Only the first pieces whose points add up to at most
// `max_points` are decoded (at least one piece). LAS files and LAZ files without a chunk table
// come as one piece. Throws lidarscout::Error when the tile cannot be decoded, or what
// `on_piece` throws (the pieces under way finish first).
void decode_tile_pieces(const dataset::DatasetTile& tile, std::uint64_t las_stride, ThreadPool& pool,
                        const PointOrder& order, std::uint64_t piece_points, std::uint64_t max_points,
                        const std::function<void(PointSet&&)>& on_piece);

}  // namespace lidarscout::viewer
