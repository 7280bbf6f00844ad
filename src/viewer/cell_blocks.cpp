// CellBlocks: block keys, the tree's grid over the tiles' extent, counts, boxes.
#include "viewer/cell_blocks.hpp"

#include <cmath>

namespace lidarscout::viewer {
namespace {

constexpr int kMaxSide = 1024;  // the tree's grid at most this many blocks a side; beyond, blocks are apart

std::int32_t floor_div(std::int32_t a, std::int32_t b) { return a >= 0 ? a / b : -((-a + b - 1) / b); }

}  // namespace

CellBlocks::CellBlocks(const lidarscout::PatchGrid& grid, const dataset::Bounds& extent_m, double z_min, double z_max)
    : grid_(&grid), z_min_(z_min), z_max_(z_max) {
    if (extent_m.empty()) return;
    const auto lo = key_of_cell(grid.cell_of(extent_m.min_x, extent_m.min_y));
    const auto hi = key_of_cell(grid.cell_of(extent_m.max_x, extent_m.max_y));
    origin_ = lo;
    nx_ = std::clamp(hi.ix - lo.ix + 1, 1, kMaxSide);
    ny_ = std::clamp(hi.iy - lo.iy + 1, 1, kMaxSide);
    for (auto& t : trees_) t = CountQuadtree(nx_, ny_);
}

CellBlocks::Key CellBlocks::key_of_cell(lidarscout::CellKey cell) const {
    return {floor_div(cell.ix, kBlockCells), floor_div(cell.iy, kBlockCells)};
}

bool CellBlocks::in_tree(Key key) const {
    const std::int64_t x = std::int64_t{key.ix} - origin_.ix, y = std::int64_t{key.iy} - origin_.iy;
    return grid_ && x >= 0 && y >= 0 && x < nx_ && y < ny_;
}

CellBlocks::Block& CellBlocks::block_of(lidarscout::CellKey cell) {
    const Key key = key_of_cell(cell);
    const auto [it, added] = blocks_.try_emplace(key);
    if (added) {
        it->second.key = key;
        if (!in_tree(key)) apart_.push_back(key);
    }
    return it->second;
}

void CellBlocks::add(List list, lidarscout::CellKey cell) {
    block_of(cell).cells[list].push_back(cell);
    count(list, cell, 1);
}

void CellBlocks::clear(List list) {
    for (auto& [key, b] : blocks_) b.cells[list].clear();
    trees_[list] = CountQuadtree(nx_, ny_);
    sizes_[list] = 0;
}

void CellBlocks::count(List list, lidarscout::CellKey cell, int delta) {
    sizes_[list] += delta;
    const Key key = key_of_cell(cell);
    if (in_tree(key)) trees_[list].add(key.ix - origin_.ix, key.iy - origin_.iy, delta);
}

dataset::Bounds CellBlocks::block_box(Key key) const {
    const double side = grid_ ? grid_->patch_size() * kBlockCells : 0;
    const double x = grid_ ? grid_->cell_min_x({key.ix * kBlockCells, 0}) : 0;
    const double y = grid_ ? grid_->cell_min_y({0, key.iy * kBlockCells}) : 0;
    return {x, y, z_min_, x + side, y + side, z_max_};
}

dataset::Bounds CellBlocks::rect_box(const LeafRect& r) const {
    dataset::Bounds b = block_box(leaf_key(r.x0, r.y0));
    const dataset::Bounds far = block_box(leaf_key(r.x1 - 1, r.y1 - 1));
    b.max_x = far.max_x, b.max_y = far.max_y;
    return b;
}

std::uint64_t CellBlocks::visits() const {
    std::uint64_t n = block_visits_;
    for (const auto& t : trees_) n += t.visits();
    return n;
}

}  // namespace lidarscout::viewer
