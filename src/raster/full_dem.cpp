// grid_full_dem: stream tiles south to north, add points to their blocks' texels, finish each
// block when its last overlapping tile is done.
#include "raster/full_dem.hpp"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <unordered_map>

#include "core/error.hpp"
#include "dataset/dataset.hpp"
#include "dataset/point_stream.hpp"

namespace lidarscout::raster {

ClassFilter ClassFilter::only(const std::vector<int>& classes) {
    ClassFilter f;
    if (classes.empty()) return f;
    f.keep.fill(false);
    for (const int c : classes) {
        if (c < 0 || c > 255) throw Error::in_stage("dem", "a class must be 0-255 (not " + std::to_string(c) + ")");
        f.keep[static_cast<std::size_t>(c)] = true;
    }
    return f;
}

std::vector<float> block_heights(std::span<const recon::TexelStats> texels, recon::TexelStatistic statistic,
                                 double z_to_metres, float nodata) {
    std::vector<float> out(texels.size(), nodata);
    for (std::size_t i = 0; i < texels.size(); ++i) {
        const float h = texels[i].height(statistic);
        if (!std::isnan(h)) out[i] = z_to_metres == 1.0 ? h : static_cast<float>(h / z_to_metres);
    }
    return out;
}

std::vector<std::uint8_t> block_rgba(std::span<const recon::TexelStats> texels) {
    const std::size_t n = texels.size();
    std::vector<std::uint8_t> out(4 * n, 0);
    for (std::size_t i = 0; i < n; ++i) {
        if (texels[i].count == 0) continue;
        for (int c = 0; c < 3; ++c) {
            out[c * n + i] = static_cast<std::uint8_t>(std::lround(texels[i].colour(c) * 255.0f));
        }
        out[3 * n + i] = 255;
    }
    return out;
}

namespace {

// Blocks (inclusive index ranges) a tile may put points into.
struct BlockRange {
    int x0 = 0, y0 = 0, x1 = -1, y1 = -1;
    bool empty() const { return x1 < x0 || y1 < y0; }
    bool contains(dataset::CellKey c) const { return c.ix >= x0 && c.ix <= x1 && c.iy >= y0 && c.iy <= y1; }
};

int block_index(double v, double origin, double block_m, int count) {
    const double i = std::floor((v - origin) / block_m);
    return static_cast<int>(std::clamp(i, -1.0, static_cast<double>(count)));
}

// The tile's header bounds grown by a texel (rounding of the bounds against the points).
BlockRange tile_blocks(const DemGrid& g, const dataset::Bounds& b) {
    const double m = g.block * g.texel_m, pad = g.texel_m;
    BlockRange r{block_index(b.min_x - pad, g.origin_x, m, g.blocks_x()),
                 block_index(b.min_y - pad, g.origin_y, m, g.blocks_y()),
                 block_index(b.max_x + pad, g.origin_x, m, g.blocks_x()),
                 block_index(b.max_y + pad, g.origin_y, m, g.blocks_y())};
    if (r.x1 < 0 || r.y1 < 0 || r.x0 >= g.blocks_x() || r.y0 >= g.blocks_y()) return {};
    r.x0 = std::max(r.x0, 0), r.y0 = std::max(r.y0, 0);
    r.x1 = std::min(r.x1, g.blocks_x() - 1), r.y1 = std::min(r.y1, g.blocks_y() - 1);
    return r;
}

class BlockSet {
public:
    BlockSet(const DemGrid& grid, const FullDemOptions& options, const DemOutputs& outputs, FullDemStats& stats)
        : grid_(grid), spec_(grid.block_spec()), options_(options), outputs_(outputs), stats_(stats),
          pending_(static_cast<std::size_t>(grid.blocks_x()) * grid.blocks_y(), 0) {}

    void expect(const BlockRange& r) { visit(r, [&](dataset::CellKey c) { ++pending_[slot(c)]; }); }

    // Adds a point of a tile whose blocks are `range`; false when it lies outside the grid.
    bool add(const dataset::MetricPoint& p, const BlockRange& range, const std::string& tile) {
        const auto at = recon::locate_texel(spec_, grid_.origin_x, grid_.origin_y, p.x, p.y);
        if (!at || at->cell.ix < 0 || at->cell.iy < 0 || at->cell.ix >= grid_.blocks_x() ||
            at->cell.iy >= grid_.blocks_y()) {
            return false;
        }
        if (at->cell.ix * grid_.block + at->col >= grid_.width || at->cell.iy * grid_.block + at->row >= grid_.height) {
            return false;
        }
        if (!range.contains(at->cell)) {
            throw Error(tile, std::nullopt, "a point at (" + std::to_string(p.x) + ", " + std::to_string(p.y) +
                                                " m) lies outside the tile's header bounds");
        }
        texels_of(at->cell)[static_cast<std::size_t>(at->row) * grid_.block + at->col].add(p.z, p.rgb);
        return true;
    }

    void tile_done(const BlockRange& r) {
        visit(r, [&](dataset::CellKey c) {
            if (--pending_[slot(c)] == 0) finish(c);
        });
    }

private:
    std::size_t slot(dataset::CellKey c) const { return static_cast<std::size_t>(c.iy) * grid_.blocks_x() + c.ix; }

    template <typename Fn>
    static void visit(const BlockRange& r, Fn&& fn) {
        for (int iy = r.y0; iy <= r.y1; ++iy) {
            for (int ix = r.x0; ix <= r.x1; ++ix) fn(dataset::CellKey{ix, iy});
        }
    }

    std::vector<recon::TexelStats>& texels_of(dataset::CellKey c) {
        if (last_ && last_key_ == c) return *last_;
        auto [it, created] = blocks_.try_emplace(c);
        if (created) {
            it->second.resize(static_cast<std::size_t>(grid_.block) * grid_.block);
            stats_.peak_blocks = std::max(stats_.peak_blocks, blocks_.size());
        }
        last_key_ = c;
        last_ = &it->second;
        return it->second;
    }

    // Blocks no point reached are left to the raster's nodata.
    void finish(dataset::CellKey c) {
        const auto it = blocks_.find(c);
        if (it == blocks_.end()) return;
        const std::span<const recon::TexelStats> texels(it->second);
        const auto heights = block_heights(texels, options_.statistic, outputs_.z_to_metres, options_.nodata);
        write_block(*outputs_.heights, grid_, 1, c.ix, c.iy, std::span<const float>(heights));
        if (outputs_.rgb) {
            const auto rgba = block_rgba(texels);
            const std::size_t plane = texels.size();
            for (int band = 0; band < 4; ++band) {
                write_block(*outputs_.rgb, grid_, band + 1, c.ix, c.iy,
                            std::span<const std::uint8_t>(rgba.data() + band * plane, plane));
            }
        }
        if (last_ == &it->second) last_ = nullptr;
        blocks_.erase(it);
        ++stats_.blocks_written;
    }

    const DemGrid& grid_;
    recon::PatchSpec spec_;
    const FullDemOptions& options_;
    const DemOutputs& outputs_;
    FullDemStats& stats_;
    std::vector<int> pending_;
    std::unordered_map<dataset::CellKey, std::vector<recon::TexelStats>, dataset::CellKeyHash> blocks_;
    dataset::CellKey last_key_;
    std::vector<recon::TexelStats>* last_ = nullptr;
};

// Tile indices south to north, then west to east, so finished rows of blocks free early.
std::vector<std::uint32_t> tile_order(const dataset::Dataset& ds) {
    std::vector<std::uint32_t> order(ds.tiles.size());
    std::iota(order.begin(), order.end(), 0u);
    std::stable_sort(order.begin(), order.end(), [&](std::uint32_t a, std::uint32_t b) {
        const auto &ba = ds.tiles[a].bounds_m, &bb = ds.tiles[b].bounds_m;
        return std::pair(ba.min_y, ba.min_x) < std::pair(bb.min_y, bb.min_x);
    });
    return order;
}

}  // namespace

FullDemStats grid_full_dem(const dataset::Dataset& ds, const DemGrid& grid, const FullDemOptions& options,
                           const DemOutputs& outputs, ThreadPool& pool) {
    if (!outputs.heights) throw Error::in_stage("dem", "no height raster to write (internal error)");
    FullDemStats stats;
    BlockSet blocks(grid, options, outputs, stats);
    std::vector<BlockRange> ranges(ds.tiles.size());
    std::uint64_t total = 0;
    for (std::size_t i = 0; i < ds.tiles.size(); ++i) {
        ranges[i] = tile_blocks(grid, ds.tiles[i].bounds_m);
        blocks.expect(ranges[i]);
        if (!ranges[i].empty()) total += ds.tiles[i].tile.header.point_count;
    }
    const std::uint32_t fields =
        laz::fields::kXyz | laz::fields::kClassification | (outputs.rgb ? laz::fields::kRgb : 0u);
    for (const std::uint32_t t : tile_order(ds)) {
        if (ranges[t].empty()) continue;
        const std::string& path = ds.tiles[t].tile.path;
        dataset::for_each_metric_batch(ds, t, pool, [&](std::uint64_t, std::span<const dataset::MetricPoint> points) {
            for (const auto& p : points) {
                if (options.classes.keep[p.classification]) stats.points_used += blocks.add(p, ranges[t], path);
            }
            stats.points_read += points.size();
            if (options.progress) options.progress(stats.points_read, total);
        }, fields);
        blocks.tile_done(ranges[t]);
    }
    return stats;
}

}  // namespace lidarscout::raster
