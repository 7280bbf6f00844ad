// CellBlocks: block keys, the tree's grid over the tiles' extent, counts, boxes.
#include "viewer/cell_blocks.hpp"

#include <cmath>

#include "render/cache_key.hpp"

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

std::uint64_t BlockChunks::bytes() const {
    return sizeof(BlockChunks) + set.points.capacity() * sizeof(render::PointAttr) +
           cells.capacity() * sizeof(lidarscout::CellKey) + ends.capacity() * sizeof(std::uint32_t);
}

std::shared_ptr<BlockChunks> read_block_chunks(const lidarscout::PatchGrid& grid, lidarscout::CellKey block,
                                               std::span<const lidarscout::CellKey> cells) {
    auto out = std::make_shared<BlockChunks>();
    const lidarscout::CellKey corner{block.ix * CellBlocks::kBlockCells, block.iy * CellBlocks::kBlockCells};
    out->set.origin_x = grid.cell_min_x(corner), out->set.origin_y = grid.cell_min_y(corner);
    for (const auto cell : cells) {
        const auto dx = static_cast<float>((cell.ix - corner.ix) * grid.patch_size());
        const auto dy = static_cast<float>((cell.iy - corner.iy) * grid.patch_size());
        grid.read_points(cell, [&](std::span<const GridPoint> points) {
            for (const GridPoint& p : points) out->set.points.push_back(chunk_point_attr(p, dx, dy));
        });
        if (out->set.points.size() == (out->ends.empty() ? 0 : out->ends.back())) continue;  // none in it
        out->cells.push_back(cell);
        out->ends.push_back(static_cast<std::uint32_t>(out->set.points.size()));
    }
    out->set.points.shrink_to_fit();
    out->set.cache_key = render::new_cache_key();
    return out;
}

PointSet chunks_without(const BlockChunks& chunks, const std::function<bool(lidarscout::CellKey)>& hidden) {
    PointSet out;
    out.origin_x = chunks.set.origin_x, out.origin_y = chunks.set.origin_y, out.origin_z = chunks.set.origin_z;
    const auto& all = chunks.set.points;
    for (std::size_t k = 0, begin = 0; k < chunks.cells.size(); begin = chunks.ends[k++]) {
        if (hidden(chunks.cells[k])) continue;
        out.points.insert(out.points.end(), all.begin() + begin, all.begin() + chunks.ends[k]);
    }
    out.points.shrink_to_fit();
    out.cache_key = render::new_cache_key();
    return out;
}

CellBlocks::Key CellBlocks::key_of_cell(lidarscout::CellKey cell) {
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
