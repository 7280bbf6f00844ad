// Level of detail for full-resolution points: blocks, their coarse-to-fine order, the level a
// camera needs, coarse copies.
#include "viewer/point_lod.hpp"

#include <algorithm>
#include <bit>
#include <cmath>
#include <numbers>
#include <unordered_map>

#include "core/radix_sort.hpp"
#include "render/cache_key.hpp"
#include "viewer/visibility.hpp"

namespace lidarscout::viewer {
namespace {

constexpr std::size_t kFinestCell = kLodLevels - 2;  // level 16: cells of block_m / 65536

// Spreads the low 16 bits of v to the even bits.
std::uint32_t spread_bits(std::uint32_t v) {
    v &= 0xffff;
    v = (v | (v << 8)) & 0x00ff00ff;
    v = (v | (v << 4)) & 0x0f0f0f0f;
    v = (v | (v << 2)) & 0x33333333;
    v = (v | (v << 1)) & 0x55555555;
    return v;
}

std::uint32_t axis_cell(double t) { return static_cast<std::uint32_t>(std::clamp(t * 65536.0, 0.0, 65535.0)); }

// Sorts `keyed` (code << 32 | index) by code, stably.
void sort_by_code(std::vector<std::uint64_t>& keyed) { radix_sort(keyed, [](std::uint64_t k) { return k >> 32; }, 32); }

// Which block of the world grid each point falls in; blocks numbered in order of first appearance.
struct BlockIndex {
    std::vector<std::uint32_t> of_point;
    std::vector<std::pair<std::int64_t, std::int64_t>> cells;  // per block: its grid cell
};

BlockIndex index_blocks(const PointSet& tile, double block_m) {
    BlockIndex out;
    out.of_point.resize(tile.points.size());
    std::unordered_map<std::uint64_t, std::uint32_t> ids;
    std::uint64_t last_key = 0;
    std::uint32_t last_id = 0;
    for (std::size_t i = 0; i < tile.points.size(); ++i) {
        const auto& p = tile.points[i];
        const auto ix = static_cast<std::int64_t>(std::floor((tile.origin_x + p.dx) / block_m));
        const auto iy = static_cast<std::int64_t>(std::floor((tile.origin_y + p.dy) / block_m));
        const std::uint64_t key = (static_cast<std::uint64_t>(ix) << 32) ^ static_cast<std::uint32_t>(iy);
        if (i == 0 || key != last_key) {  // points come in scan order: mostly the previous point's block
            const auto [it, added] = ids.try_emplace(key, static_cast<std::uint32_t>(out.cells.size()));
            if (added) out.cells.emplace_back(ix, iy);
            last_key = key, last_id = it->second;
        }
        out.of_point[i] = last_id;
    }
    return out;
}

dataset::Bounds bounds_of(const PointSet& set) {
    dataset::Bounds b;
    for (const auto& p : set.points) {
        const double x = set.origin_x + p.dx, y = set.origin_y + p.dy, z = set.origin_z + p.dz;
        b.min_x = std::min(b.min_x, x), b.max_x = std::max(b.max_x, x);
        b.min_y = std::min(b.min_y, y), b.max_y = std::max(b.max_y, y);
        b.min_z = std::min(b.min_z, z), b.max_z = std::max(b.max_z, z);
    }
    return b;
}

// The level of each point of a block, its points sorted by quadtree code (`keyed`: code << 32 |
// index into `members`): the coarsest level at which it is the highest point of its cell (ties:
// the first), so that every cell's representative is what a view from above sees first;
// points sharing their finest cell with a higher one get the last level. One pass: the open
// cell of every level keeps its highest point so far, a cell that ends hands its highest to
// its parent (so a point costs the levels where it starts a cell, not every level). Cells that
// hold one point only (the last one's, from the level where it parted from the point before)
// end together in one step.
std::vector<std::uint8_t> point_levels(const PointSet& tile, std::span<const std::uint32_t> members,
                                       std::span<const std::uint64_t> keyed) {
    const std::size_t n = keyed.size();
    std::vector<std::uint8_t> level(n, static_cast<std::uint8_t>(kLodLevels - 1));
    if (n == 0) return level;
    std::vector<float> z(n);
    for (std::size_t i = 0; i < n; ++i) z[i] = tile.points[members[static_cast<std::uint32_t>(keyed[i])]].dz;
    std::array<std::size_t, kFinestCell + 1> best{};  // per level: the highest point of its open cell
    std::size_t alone = 0;  // open cells of levels [alone, kFinestCell] hold the last point only
    // Ends the open cells of levels [from, kFinestCell], finest first.
    const auto end_cells = [&](std::size_t from) {
        std::size_t k = kFinestCell + 1;
        if (const std::size_t top = std::max(from, alone); top <= kFinestCell) {  // [top, finest]: one point
            level[best[top]] = std::min(level[best[top]], static_cast<std::uint8_t>(top));
            if (top > 0 && z[best[top]] > z[best[top - 1]]) best[top - 1] = best[top];
            k = top;
        }
        while (k-- > from) {
            level[best[k]] = std::min(level[best[k]], static_cast<std::uint8_t>(k));
            if (k > 0 && z[best[k]] > z[best[k - 1]]) best[k - 1] = best[k];
        }
    };
    for (std::size_t i = 1; i < n; ++i) {
        const std::size_t split = first_level(static_cast<std::uint32_t>(keyed[i] >> 32),
                                              static_cast<std::uint32_t>(keyed[i - 1] >> 32));
        if (split > kFinestCell) {  // the same finest cell as the previous point
            if (z[i] > z[best[kFinestCell]]) best[kFinestCell] = i;
            alone = kLodLevels;  // every open cell holds two points now
            continue;
        }
        end_cells(split);
        std::fill(best.begin() + static_cast<std::ptrdiff_t>(split), best.end(), i);
        alone = split;
    }
    end_cells(0);
    return level;
}

// One block from the indices of its points in `tile` (scan order).
LodBlock make_block(const PointSet& tile, std::span<const std::uint32_t> members,
                    std::pair<std::int64_t, std::int64_t> cell, double block_m) {
    const double x0 = static_cast<double>(cell.first) * block_m, y0 = static_cast<double>(cell.second) * block_m;
    std::vector<std::uint64_t> keyed(members.size());  // code << 32 | position in `members`
    for (std::size_t i = 0; i < members.size(); ++i) {
        const auto& p = tile.points[members[i]];
        const double u = (tile.origin_x + p.dx - x0) / block_m, v = (tile.origin_y + p.dy - y0) / block_m;
        keyed[i] = (std::uint64_t{quadtree_code(u, v)} << 32) | i;
    }
    sort_by_code(keyed);
    const std::vector<std::uint8_t> level = point_levels(tile, members, keyed);
    std::array<std::uint32_t, kLodLevels> count{};
    for (const auto l : level) ++count[l];
    LodBlock block;
    block.size_m = block_m;
    std::array<std::uint32_t, kLodLevels> next{};
    for (std::size_t k = 0, sum = 0; k < kLodLevels; ++k) {
        next[k] = static_cast<std::uint32_t>(sum);
        sum += count[k];
        block.level_end[k] = static_cast<std::uint32_t>(sum);
        block.level_key[k] = render::new_cache_key();
    }
    block.points.origin_x = tile.origin_x, block.points.origin_y = tile.origin_y, block.points.origin_z = tile.origin_z;
    block.points.spacing_m = tile.spacing_m;
    block.points.points.resize(keyed.size());
    for (std::size_t i = 0; i < keyed.size(); ++i) {
        block.points.points[next[level[i]]++] = tile.points[members[static_cast<std::uint32_t>(keyed[i])]];
    }
    block.bounds = bounds_of(block.points);
    count_classes(block.points);
    return block;
}

}  // namespace

double LodBlock::spacing(std::size_t level) const {
    return level > kFinestCell ? 0.0 : size_m / static_cast<double>(1u << level);
}

render::PointBatch LodBlock::prefix(std::size_t level) const {
    const std::size_t l = std::min(level, levels - 1);
    return {points.origin_x,
            points.origin_y,
            points.origin_z,
            std::span(points.points.data(), level_end[l]),
            level_key[l],
            std::max(static_cast<float>(spacing(l)), points.spacing_m)};
}

std::uint32_t quadtree_code(double u, double v) { return spread_bits(axis_cell(u)) | (spread_bits(axis_cell(v)) << 1); }

std::size_t first_level(std::uint32_t code, std::uint32_t previous) {
    const std::uint32_t diff = code ^ previous;
    if (diff == 0) return kLodLevels - 1;
    const int high = 31 - std::countl_zero(diff);  // the level-k cell is the code's top 2k bits
    return static_cast<std::size_t>((32 - high + 1) / 2);
}

LodBlocks build_lod_blocks(const PointSet& tile, std::uint32_t tile_index, double block_m, ThreadPool& pool) {
    const BlockIndex index = index_blocks(tile, block_m);
    std::vector<std::uint32_t> start(index.cells.size() + 1, 0);
    for (const auto b : index.of_point) ++start[b + 1];
    for (std::size_t b = 1; b < start.size(); ++b) start[b] += start[b - 1];
    std::vector<std::uint32_t> members(tile.points.size());
    {
        std::vector<std::uint32_t> fill(start.begin(), start.end() - 1);
        for (std::uint32_t i = 0; i < index.of_point.size(); ++i) members[fill[index.of_point[i]]++] = i;
    }
    LodBlocks out(index.cells.size());
    pool.for_each(index.cells.size(), [&](std::size_t b) {
        auto block = std::make_shared<LodBlock>(make_block(
            tile, std::span(members).subspan(start[b], start[b + 1] - start[b]), index.cells[b], block_m));
        block->tile = tile_index;
        block->points.cache_key = block->level_key[kLodLevels - 1];
        out[b] = std::move(block);
    });
    return out;
}

std::size_t coarse_level(const LodBlock& block, double spacing_m) {
    const double ratio = block.size_m / std::max(spacing_m, 1e-9);
    return static_cast<std::size_t>(std::clamp(std::floor(std::log2(std::max(ratio, 1.0))), 0.0,
                                               static_cast<double>(block.levels - 1)));
}

std::shared_ptr<const LodBlock> coarse_copy(const LodBlock& block, double spacing_m) {
    const std::size_t keep = coarse_level(block, spacing_m);
    auto out = std::make_shared<LodBlock>();
    out->points.origin_x = block.points.origin_x, out->points.origin_y = block.points.origin_y;
    out->points.origin_z = block.points.origin_z;
    out->points.spacing_m = block.points.spacing_m;
    const auto& src = block.points.points;
    out->points.points.assign(src.begin(), src.begin() + block.level_end[keep]);
    out->level_end = block.level_end, out->level_key = block.level_key;
    out->levels = keep + 1;
    out->points.cache_key = block.level_key[keep];
    count_classes(out->points);
    out->size_m = block.size_m, out->bounds = block.bounds, out->tile = block.tile;
    return out;
}

std::uint64_t lod_bytes(const LodBlocks& blocks) {
    std::uint64_t n = 0;
    for (const auto& b : blocks) n += b->bytes();
    return n;
}

std::uint64_t lod_points(const LodBlocks& blocks) {
    std::uint64_t n = 0;
    for (const auto& b : blocks) n += b->points.points.size();
    return n;
}

double pixel_footprint(const render::Camera& camera, double distance) {
    const double half = std::tan(0.5 * camera.fov_deg * std::numbers::pi / 180.0);
    return 2.0 * std::max(distance, camera.near_m) * half / std::max(1, camera.height);
}

std::size_t level_for(const LodBlock& block, const render::Camera& camera, double spacing_px) {
    if (spacing_px <= 0) return block.levels - 1;
    const double target = spacing_px * pixel_footprint(camera, distance_to(camera, block.bounds));
    const double k = std::ceil(std::log2(block.size_m / target));
    if (!(k < static_cast<double>(kFinestCell))) return block.levels - 1;
    return std::min(static_cast<std::size_t>(std::max(k, 0.0)), block.levels - 1);
}

std::vector<render::PointBatch> lod_batches(const LodBlocks& blocks, const render::Camera& camera, double spacing_px) {
    std::vector<render::PointBatch> out;
    out.reserve(blocks.size());
    for (const auto& b : blocks) {
        if (!box_in_view(camera, b->bounds)) continue;
        out.push_back(b->prefix(level_for(*b, camera, spacing_px)));
    }
    return out;
}

}  // namespace lidarscout::viewer
