// The scheduler's patch cells grouped in square blocks (16 x 16 cells, about 10 km) under count
// quadtrees (core/count_quadtree.hpp), one per list of cells it keeps: cells whose linear
// heightmap is ready to build, cells waiting for the network, cells with something to draw. So
// the work of a frame or a tick follows what is in view and what changed, never the number of
// patches: the next heightmap job is the nearest ready cell, found best first over the blocks;
// a snapshot visits the blocks in view only. The blocks' grid covers the tiles' extent given at
// construction; blocks outside it (cells of a tile whose header bounds are far larger than its
// data) are kept apart and always examined. Not thread-safe: the scheduler's lock guards it.
#pragma once

#include <algorithm>
#include <array>
#include <cstdint>
#include <functional>
#include <limits>
#include <memory>
#include <optional>
#include <span>
#include <unordered_map>
#include <vector>

#include "core/count_quadtree.hpp"
#include "dataset/dataset.hpp"
#include "core/patch_grid.hpp"
#include "viewer/patch_heightmap.hpp"
#include "viewer/point_sets.hpp"

namespace lidarscout::viewer {

// A block's chunk points: those of every cell of it that has any, read from the grid cell by cell into one set
// (origin: the block's min corner at z 0), so that a country's 600,000 cells of about nine chunk points each are
// drawn and snapshot as a few thousand sets, not as a set (and a batch, a pointer in every snapshot) each.
struct BlockChunks {
    PointSet set;
    std::vector<lidarscout::CellKey> cells;  // sorted (sort_cells)
    std::vector<std::uint32_t> ends;         // cells[k]'s points end there in set.points (they start at ends[k-1])

    // Heap bytes held (what the memory ledger counts).
    std::uint64_t bytes() const;
};

// The chunk points of `cells` (sorted, in block `block`: CellBlocks::key_of_cell), read from `grid` (cells that
// hold none left out); its set's origin the block's min corner at z 0, its cache key a new one.
std::shared_ptr<BlockChunks> read_block_chunks(const lidarscout::PatchGrid& grid, lidarscout::CellKey block,
                                               std::span<const lidarscout::CellKey> cells);
// A copy of `chunks`' set without the points of the cells `hidden` says (a heightmap shows them), a new cache key.
PointSet chunks_without(const BlockChunks& chunks, const std::function<bool(lidarscout::CellKey)>& hidden);

class CellBlocks {
public:
    enum List { Ready, CnnReady, Drawable, kLists };
    static constexpr int kBlockCells = 16;  // a block's side, in cells

    struct Block {
        lidarscout::CellKey key;  // (bx, by): cells [bx * kBlockCells, (bx + 1) * kBlockCells) on x, the same on y
        std::array<std::vector<lidarscout::CellKey>, kLists> cells;
        bool changed = true;  // a drawable cell of it changed since `shown` and `chunk_points` were listed
        // What its drawable cells show (the scheduler's per-block part of a snapshot).
        std::vector<std::shared_ptr<const PatchHeightmap>> shown;
        std::vector<std::shared_ptr<const PointSet>> chunk_points;  // none, or its chunks' (or a copy without the
                                                                    // cells that show a heightmap)
        std::shared_ptr<const BlockChunks> chunks;                  // null: none of its cells has chunk points
        std::uint64_t listed_bytes = 0;  // what chunk_points holds beyond `chunks` (a copy), in the ledger
    };

    CellBlocks() = default;
    // Blocks over the cells of `extent_m` (x, y) of `grid`, boxes between heights z_min and z_max.
    CellBlocks(const lidarscout::PatchGrid& grid, const dataset::Bounds& extent_m, double z_min, double z_max);

    void add(List list, lidarscout::CellKey cell);
    void clear(List list);
    std::size_t size(List list) const { return sizes_[list]; }
    // The block holding `cell` (created when missing).
    Block& block_of(lidarscout::CellKey cell);
    // The key of the block holding `cell` (Block::key).
    static lidarscout::CellKey key_of_cell(lidarscout::CellKey cell);
    // The box of block `b`'s cells (metres, z_min..z_max).
    dataset::Bounds box(const Block& b) const { return block_box(b.key); }

    // Removes and returns the cell of `list` of least cell_cost(cell), best first over blocks whose
    // box_cost(Bounds) is at most any of their cells' cost; nullopt when the list is empty.
    template <class BoxCost, class CellCost>
    std::optional<lidarscout::CellKey> take_nearest(List list, BoxCost&& box_cost, CellCost&& cell_cost) {
        if (sizes_[list] == 0) return std::nullopt;
        struct Best {
            Block* block = nullptr;
            std::size_t at = 0;  // the cell's index in the block's list
            double cost = std::numeric_limits<double>::infinity();
        };
        const auto best_in = [&](Block& b, Best& best) {
            const auto& cells = b.cells[list];
            for (std::size_t i = 0; i < cells.size(); ++i) {
                if (const double c = cell_cost(cells[i]); !best.block || c < best.cost) best = {&b, i, c};
            }
        };
        Best best;
        for (const auto& key : apart_) best_in(blocks_.at(key), best);
        const auto leaf = trees_[list].nearest([&](const LeafRect& r) { return box_cost(rect_box(r)); },
                                               [&](int x, int y) {
                                                   Best in;
                                                   best_in(blocks_.at(leaf_key(x, y)), in);
                                                   return in.cost;
                                               });
        if (leaf) best_in(blocks_.at(leaf_key(leaf->first, leaf->second)), best);
        if (!best.block) return std::nullopt;
        auto& cells = best.block->cells[list];
        const std::size_t at = best.at;
        const lidarscout::CellKey cell = cells[at];
        cells[at] = cells.back();
        cells.pop_back();
        count(list, cell, -1);
        return cell;
    }

    // Calls fn(Block&) for every block with cells of `list` whose box passes keep(Bounds) (a
    // conservative test: a node's box that fails it is skipped whole).
    template <class Keep, class Fn>
    void visit(List list, Keep&& keep, Fn&& fn) {
        for (const auto& key : apart_) {
            Block& b = blocks_.at(key);
            ++block_visits_;
            if (!b.cells[list].empty() && keep(block_box(key))) fn(b);
        }
        trees_[list].visit([&](const LeafRect& r) { return keep(rect_box(r)); },
                           [&](int x, int y) {
                               ++block_visits_;
                               fn(blocks_.at(leaf_key(x, y)));
                           });
    }

    // Every block (apart or not), for a whole pass (a camera-less snapshot, the loader's end).
    template <class Fn>
    void for_each(Fn&& fn) {
        for (auto& [key, b] : blocks_) fn(b);
    }

    // Nodes and blocks examined so far (for tests counting per-frame work).
    std::uint64_t visits() const;

private:
    using Key = lidarscout::CellKey;  // a block's (bx, by)
    Key leaf_key(int x, int y) const { return {origin_.ix + x, origin_.iy + y}; }
    bool in_tree(Key key) const;
    void count(List list, lidarscout::CellKey cell, int delta);
    dataset::Bounds block_box(Key key) const;
    dataset::Bounds rect_box(const LeafRect& r) const;

    const lidarscout::PatchGrid* grid_ = nullptr;
    double z_min_ = 0, z_max_ = 0;
    Key origin_{};  // the tree's leaf (0, 0)
    int nx_ = 1, ny_ = 1;
    std::unordered_map<Key, Block, lidarscout::CellKeyHash> blocks_;
    std::vector<Key> apart_;  // blocks outside the tree's grid
    std::array<CountQuadtree, kLists> trees_;
    std::array<std::size_t, kLists> sizes_{};
    mutable std::uint64_t block_visits_ = 0;
};

}  // namespace lidarscout::viewer
