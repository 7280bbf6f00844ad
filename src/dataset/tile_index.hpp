// Tiles by position, built once when a dataset opens, so that the viewer's per-frame and
// per-tick work follows what is in view and not the number of tiles: a grid of square cells over
// the tiles' centres (each tile in the cell of its centre; cells about a tile wide) under a count
// quadtree (core/count_quadtree.hpp). A tile far larger than the others (header bounds of a
// billion metres around a few points) would make every cell huge: those are kept apart and
// always examined. Two questions:
//   - visit(keep, fn): every tile whose bounds may pass `keep` (a frustum test), visiting only the
//     nodes whose box (their tiles' bounds, widened by the largest tile's reach) passes it;
//   - nearest_pending(x, y): of the tiles marked pending, the one nearest to (x, y) in the xy plane
//     (the chunk-point loader's next tile), best first.
// Not thread-safe: its owner locks.
#pragma once

#include <cstddef>
#include <cstdint>
#include <optional>
#include <span>
#include <vector>

#include "core/count_quadtree.hpp"
#include "dataset/dataset.hpp"

namespace lidarscout::dataset {

class TileIndex {
public:
    TileIndex() = default;
    // Tiles with empty bounds are never returned.
    explicit TileIndex(std::span<const Bounds> bounds);
    explicit TileIndex(const Dataset& dataset);

    // Calls fn(tile) for every tile whose bounds pass keep(Bounds); keep must pass a box whenever
    // it passes a box inside it (a frustum test does).
    template <class Keep, class Fn>
    void visit(Keep&& keep, Fn&& fn) const {
        const auto take = [&](std::uint32_t t) {
            ++tile_visits_;
            if (keep(bounds_[t])) fn(t);
        };
        for (const auto t : apart_) take(t);
        all_.visit([&](const LeafRect& r) { return keep(node_box(r)); },
                   [&](int x, int y) {
                       for (const auto t : cell_tiles(x, y)) take(t);
                   });
    }

    // Pending tiles (none at first): nearest_pending() returns only those.
    void set_pending(std::uint32_t tile, bool pending);
    bool pending(std::uint32_t tile) const { return tile < pending_.size() && pending_[tile]; }
    std::size_t pending_count() const { return pending_total_; }
    // The pending tile whose bounds are nearest to (x, y) (distance_xy; ties: the lower index).
    std::optional<std::uint32_t> nearest_pending(double x, double y) const;
    // The `most` pending tiles nearest to (x, y), nearest first (the same order as asking nearest_pending
    // `most` times, each found one taken off pending), from one search.
    std::vector<std::uint32_t> nearest_pending(double x, double y, std::size_t most) const;

    std::size_t size() const { return bounds_.size(); }
    const Bounds& bounds(std::uint32_t tile) const { return bounds_[tile]; }
    // Work done so far: quadtree nodes and tiles examined (for tests counting per-frame work).
    std::uint64_t visits() const { return all_.visits() + pending_tree_.visits() + tile_visits_; }

private:
    std::span<const std::uint32_t> cell_tiles(int x, int y) const;
    // The box holding every tile bounds of the cells in `r` (their centres' cells widened by the reach).
    Bounds node_box(const LeafRect& r) const;
    double distance_xy(const LeafRect& r, double x, double y) const;

    std::vector<Bounds> bounds_;
    std::vector<std::uint32_t> apart_;  // tiles too large for the grid (and empty-bounds tiles are in neither)
    double origin_x_ = 0, origin_y_ = 0, cell_m_ = 1, reach_ = 0;  // reach: how far a tile sticks out of its cell
    double min_z_ = 0, max_z_ = 0;
    int nx_ = 1, ny_ = 1;
    std::vector<std::int32_t> cell_;           // per tile: its cell (row-major), -1 when apart or empty
    std::vector<std::uint32_t> starts_, ids_;  // per cell (row-major) its tiles: ids_[starts_[c] .. starts_[c + 1])
    CountQuadtree all_, pending_tree_;
    std::vector<bool> pending_;
    std::size_t pending_total_ = 0;
    mutable std::uint64_t tile_visits_ = 0;
};

}  // namespace lidarscout::dataset
