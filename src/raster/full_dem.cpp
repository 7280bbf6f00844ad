// grid_full_dem: stream tiles south to north, give points to the blocks within their reach,
// finish each block when the last tile that reaches it is done.
#include "raster/full_dem.hpp"

#include <algorithm>
#include <cmath>
#include <memory>
#include <numeric>
#include <unordered_map>

#include "core/error.hpp"
#include "core/thread_pool.hpp"
#include "dataset/dataset.hpp"
#include "dataset/point_stream.hpp"
#include "raster/dem_blocks.hpp"

namespace lidarscout::raster {

namespace {

// Points read and placed at a time (a batch of a tile; the next one is read while this one is gridded).
constexpr std::uint64_t kReadBatchPoints = 1u << 20;

int block_index(double v, double origin, double block_m, int count) {
    const double i = std::floor((v - origin) / block_m);
    return static_cast<int>(std::clamp(i, -1.0, static_cast<double>(count)));
}

// The tile's header bounds grown by a texel (rounding of the bounds against the points) and the
// gridder's reach.
BlockRange tile_blocks(const DemGrid& g, const dataset::Bounds& b, double reach_m) {
    const double m = g.block * g.texel_m, pad = g.texel_m + reach_m;
    BlockRange r{block_index(b.min_x - pad, g.origin_x, m, g.blocks_x()),
                 block_index(b.min_y - pad, g.origin_y, m, g.blocks_y()),
                 block_index(b.max_x + pad, g.origin_x, m, g.blocks_x()),
                 block_index(b.max_y + pad, g.origin_y, m, g.blocks_y())};
    if (r.x1 < 0 || r.y1 < 0 || r.x0 >= g.blocks_x() || r.y0 >= g.blocks_y()) return {};
    r.x0 = std::max(r.x0, 0), r.y0 = std::max(r.y0, 0);
    r.x1 = std::min(r.x1, g.blocks_x() - 1), r.y1 = std::min(r.y1, g.blocks_y() - 1);
    return r;
}

enum class Added { Used, Missed, OutsideTile };

// The blocks in flight, each with one gridder per layer.
class BlockSet {
public:
    BlockSet(const DemGrid& grid, std::span<const GridLayer> layers, const BlockWriteFn& write, FullDemStats& stats)
        : grid_(grid), spec_(grid.block_spec()), layers_(layers), write_(write), stats_(stats), reach_(0),
          selected_(grid.selected_blocks()), pending_(static_cast<std::size_t>(grid.blocks_x()) * grid.blocks_y(), 0) {
        for (std::size_t i = 0; i < layers.size(); ++i) {
            const double reach = gridder_reach_m(layers[i].gridder, grid.texel_m);
            reach_ = std::max(reach_, reach);
            if (reach == 0) own_only_ |= 1u << i;
        }
    }

    double reach_m() const { return reach_; }

    void expect(const BlockRange& r) {
        visit(r.intersection(selected_), [&](lidarscout::CellKey c) { ++pending_[slot(c)]; });
    }

    // Adds a point of a tile whose blocks are `range` to the layers of `mask`: Used, Missed when it
    // reaches no block, OutsideTile (and not added) when it reaches a block beyond the tile's header
    // bounds, which may already be written. A layer of reach 0 gets only the points in its block.
    Added add(const dataset::MetricPoint& p, const BlockRange& range, std::uint32_t mask) {
        const auto at = recon::locate_texel(spec_, grid_.origin_x, grid_.origin_y, p.x, p.y);
        if (!at) return Added::Missed;
        const bool inside = inside_raster(*at);
        if (reach_ == 0 || (mask & ~own_only_) == 0) {
            if (!inside) return Added::Missed;
            if (!range.contains(at->cell)) return Added::OutsideTile;
            add_to(at->cell, p, &*at, *at, mask);
            return Added::Used;
        }
        const BlockRange reached = blocks_within(p.x, p.y);
        if (reached.empty()) return Added::Missed;
        if (!range.contains(reached)) return Added::OutsideTile;
        visit(reached, [&](lidarscout::CellKey c) {
            const bool own = c == at->cell && inside;
            add_to(c, p, own ? &*at : nullptr, *at, own ? mask : mask & ~own_only_);
        });
        return Added::Used;
    }

    // The blocks the tile was the last to reach are gridded in parallel, then written in order.
    void tile_done(const BlockRange& r, ThreadPool& pool) {
        std::uint64_t held = 0;
        for (const auto& [key, gridders] : blocks_) {
            for (const auto& g : gridders) held += g->held_points();
        }
        stats_.peak_held_points = std::max(stats_.peak_held_points, held);
        std::vector<std::pair<lidarscout::CellKey, Gridders>> done;
        visit(r.intersection(selected_), [&](lidarscout::CellKey c) {
            if (--pending_[slot(c)] != 0) return;
            const auto it = blocks_.find(c);  // blocks no point reached are left to the raster's nodata
            if (it == blocks_.end()) return;
            if (last_ == &it->second) last_ = nullptr;
            done.emplace_back(c, std::move(it->second));
            blocks_.erase(it);
        });
        const std::size_t n = layers_.size();
        std::vector<std::vector<BlockImages>> images(done.size(), std::vector<BlockImages>(n));
        pool.for_each(done.size() * n, [&](std::size_t i) {
            auto& gridder = done[i / n].second[i % n];
            images[i / n][i % n] = gridder->finish();
            gridder.reset();
        });
        for (std::size_t i = 0; i < done.size(); ++i) {
            write_(done[i].first, images[i]);
            ++stats_.blocks_written;
        }
    }

private:
    using Gridders = std::vector<std::unique_ptr<BlockGridder>>;

    std::size_t slot(lidarscout::CellKey c) const { return static_cast<std::size_t>(c.iy) * grid_.blocks_x() + c.ix; }

    bool inside_raster(const recon::TexelLocation& at) const {
        return at.cell.ix >= 0 && at.cell.iy >= 0 && at.cell.ix < grid_.blocks_x() && at.cell.iy < grid_.blocks_y() &&
               at.cell.ix * grid_.block + at.col < grid_.width && at.cell.iy * grid_.block + at.row < grid_.height;
    }

    // The blocks of the grid within the reach of (x, y).
    BlockRange blocks_within(double x, double y) const {
        const double m = grid_.block * grid_.texel_m;
        BlockRange r{block_index(x - reach_, grid_.origin_x, m, grid_.blocks_x()),
                     block_index(y - reach_, grid_.origin_y, m, grid_.blocks_y()),
                     block_index(x + reach_, grid_.origin_x, m, grid_.blocks_x()),
                     block_index(y + reach_, grid_.origin_y, m, grid_.blocks_y())};
        r.x0 = std::max(r.x0, 0), r.y0 = std::max(r.y0, 0);
        r.x1 = std::min(r.x1, grid_.blocks_x() - 1), r.y1 = std::min(r.y1, grid_.blocks_y() - 1);
        return r;
    }

    template <typename Fn>
    static void visit(const BlockRange& r, Fn&& fn) {
        for (int iy = r.y0; iy <= r.y1; ++iy) {
            for (int ix = r.x0; ix <= r.x1; ++ix) fn(lidarscout::CellKey{ix, iy});
        }
    }

    void add_to(lidarscout::CellKey c, const dataset::MetricPoint& p, const recon::TexelLocation* own,
                const recon::TexelLocation& at, std::uint32_t mask) {
        if (mask == 0 || !selected_.contains(c)) return;  // a block of another `dem --block`
        Gridders& g = gridders_of(c);
        for (std::size_t i = 0; mask != 0; ++i, mask >>= 1) {
            if (mask & 1u) g[i]->add_located(p, own, at);
        }
    }

    Gridders& gridders_of(lidarscout::CellKey c) {
        if (last_ && last_key_ == c) return *last_;
        auto [it, created] = blocks_.try_emplace(c);
        if (created) {
            for (const GridLayer& l : layers_) it->second.push_back(make_block_gridder(l.gridder, grid_, c));
            stats_.peak_blocks = std::max(stats_.peak_blocks, blocks_.size());
        }
        last_key_ = c;
        last_ = &it->second;
        return *last_;
    }

    const DemGrid& grid_;
    recon::PatchSpec spec_;
    std::span<const GridLayer> layers_;
    const BlockWriteFn& write_;
    FullDemStats& stats_;
    double reach_;
    BlockRange selected_;
    std::uint32_t own_only_ = 0;  // layers of reach 0
    std::vector<int> pending_;
    std::unordered_map<lidarscout::CellKey, Gridders, lidarscout::CellKeyHash> blocks_;
    lidarscout::CellKey last_key_;
    Gridders* last_ = nullptr;
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

// What a block's gridder holds per texel (block_gridders.cpp) plus its finished images (heights
// and colour): TexelStats is 32 bytes; idw sums 16, colour sums 24; tin about one held point of
// 48 bytes per texel at survey densities; highest-tin a highest point of 32 bytes per texel of the
// block and its margin (1.8 times the block's) and the tin of those.
std::uint64_t gridder_bytes_per_texel(const GridderSpec& g) {
    const std::uint64_t images = 4 + (g.rgb ? 4 : 0);
    switch (g.method) {
        case GridMethod::Statistic: return 32 + images;
        case GridMethod::Idw: return 16 + (g.rgb ? 24 : 0) + images;
        case GridMethod::Tin: return 48 + images;
        case GridMethod::HighestTin: return 58 + 48 + images;
    }
    return 48 + images;
}

// A tin block holds every point of the block and its margin until it is finished (24 bytes each, in
// chunks of 65,536: at most one chunk more); finishing one copies them, sorts them into the patch and
// triangulates them (about 240 bytes a point at its peak, measured) or, from kTinWalkPointsPerTexel
// on, sorts them into buckets and walks (about 120 bytes). Where the points are denser than a
// texel, these outweigh the per-texel bytes. The points held at once lie in one band across the
// selected blocks (held_points_estimate), and the densest block finishes on top. Measured on the
// 2,025-tile replica's 10 m dtm of every point: the run held 9.76 GB at its peak, estimated 16.4 GB
// (the blocks' mean times the rows of blocks a tile reaches plus one had estimated 24.7 GB).
// A tin block with the ground filter also holds, while it finishes, its lattice (about 60 bytes a
// cell at the peak: the surfaces, the masks, the running extremes, the pull-push pyramid) and 33
// bytes per point (a sample, its cell, its verdict).
double ground_filter_bytes(const DemGrid& grid, const GridderSpec& tin, double points) {
    const int margin = tin_margin_texels(tin, grid.texel_m);
    const double cells = tin_ground_lattice(grid, margin, 0, 0, *tin.ground).cells;
    return cells * cells * 60 + points * 33;
}

// The reading: two batches at once, each as placed points, as records and (at most about as large)
// their compressed bytes; and the program itself (its code and libraries, about 50 MB resident).
// On ky-jmo335 at 1 m the plain mean DEM held 0.36 GB at its peak, 0.24 GB estimated without these.
double reading_bytes(const dataset::Dataset& ds) {
    constexpr double kProgramBytes = 64e6;
    double record = 0;
    for (const auto& t : ds.tiles) record = std::max(record, static_cast<double>(t.tile.header.record_length));
    return kProgramBytes + 2.0 * kReadBatchPoints * (sizeof(dataset::MetricPoint) + 2 * record);
}

constexpr double kHeldChunkBytes = 65536.0 * 24;

// The height of the band that holds every point held at once. Tiles are read south to north (by
// their southern edge, tile_order) and a block is finished when the last tile that reaches it is
// done; so when the tiles up to a southern edge y are done, a block still held reaches a tile not
// yet read, whose grown range (tile_blocks) starts at y - texel - reach at the lowest: the block's
// northern edge lies above that, and its points (its margin included) above y - texel - 2 reach -
// block. The points read so far end at y + the tallest tile's height + a texel (a point further
// outside its tile's bounds is refused).
double held_band_m(const dataset::Dataset& ds, const DemGrid& g, double reach_m) {
    double tallest = 0;
    for (const auto& t : ds.tiles) tallest = std::max(tallest, t.bounds_m.max_y - t.bounds_m.min_y);
    return g.block * g.texel_m + 2 * g.texel_m + 2 * reach_m + tallest;
}

// The most points (the tiles' headers, spread evenly over their bounds) in any band `band_m` high
// across the selected blocks and their reach: summed over strips of an eighth of the band, the
// band's nine strips that hold the most (so at most an eighth too many).
double densest_band_points(const dataset::Dataset& ds, const DemGrid& g, double band_m, double reach_m) {
    const BlockRange sel = g.selected_blocks();
    const double m = g.block * g.texel_m;
    const double x0 = g.origin_x + sel.x0 * m - reach_m, x1 = g.origin_x + (sel.x1 + 1) * m + reach_m;
    const double y0 = g.origin_y + sel.y0 * m - reach_m, y1 = g.origin_y + (sel.y1 + 1) * m + reach_m;
    constexpr int kStripsPerBand = 8;
    const double strip = band_m / kStripsPerBand;
    const auto strips = static_cast<std::size_t>(std::clamp(std::ceil((y1 - y0) / strip), 1.0, double(1 << 22)));
    std::vector<double> in_strip(strips, 0.0);
    const auto strip_of = [&](double y) {
        return static_cast<std::size_t>(std::clamp(std::floor((y - y0) / strip), 0.0, double(strips - 1)));
    };
    for (const auto& t : ds.tiles) {
        const auto& b = t.bounds_m;
        const double points = static_cast<double>(t.tile.header.point_count);
        const double w = b.max_x - b.min_x, h = b.max_y - b.min_y;
        const double across = std::min(b.max_x, x1) - std::max(b.min_x, x0);
        if (across < 0 || b.max_y < y0 || b.min_y > y1) continue;
        const double share = w > 0 ? across / w : 1.0;  // a tile without width goes whole
        for (std::size_t i = strip_of(b.min_y); i <= strip_of(b.max_y); ++i) {
            const double s0 = y0 + double(i) * strip;
            const double over = std::min(b.max_y, s0 + strip) - std::max(b.min_y, s0);
            in_strip[i] += points * share * (h > 0 ? std::max(0.0, over) / h : 1.0);
        }
    }
    double window = 0, most = 0;
    for (std::size_t i = 0; i < strips; ++i) {
        window += in_strip[i];
        if (i >= kStripsPerBand + 1) window -= in_strip[i - kStripsPerBand - 1];
        most = std::max(most, window);
    }
    return most;
}

bool is_tin(const GridLayer& l) { return l.gridder.method == GridMethod::Tin; }

// A tin block's window side in texels: the block and its margin.
double tin_window_texels(const DemGrid& grid, const GridLayer& l) {
    return grid.block + 2.0 * tin_margin_texels(l.gridder, grid.texel_m);
}

// The margins' share: points within the reach of two or four blocks are held by each.
double grown_by_margin(const DemGrid& grid, const GridLayer& l) {
    const double window = tin_window_texels(grid, l);
    return window / grid.block * window / grid.block;
}

struct TinPoints {
    double held_bytes = 0, finishing_bytes = 0;  // all the blocks held at once; the densest block's finishing
    int layers = 0;                               // tin layers
};

TinPoints tin_point_bytes(const dataset::Dataset& ds, const DemGrid& grid, std::span<const GridLayer> layers) {
    if (std::none_of(layers.begin(), layers.end(), is_tin)) return {};
    const std::vector<double> points = block_point_estimates(ds, grid);
    const BlockRange selected = grid.selected_blocks();
    double densest = 0;
    for (int iy = selected.y0; iy <= selected.y1; ++iy) {
        for (int ix = selected.x0; ix <= selected.x1; ++ix) {
            densest = std::max(densest, points[static_cast<std::size_t>(iy) * grid.blocks_x() + ix]);
        }
    }
    TinPoints out;
    out.held_bytes = held_points_estimate(ds, grid, layers) * 24;
    for (const GridLayer& l : layers) {
        if (!is_tin(l)) continue;
        const double window = tin_window_texels(grid, l);
        const double seen = densest * grown_by_margin(grid, l);  // points
        out.finishing_bytes += seen * (seen >= kTinWalkPointsPerTexel * window * window ? 120 : 240);
        if (l.gridder.ground) out.finishing_bytes += ground_filter_bytes(grid, l.gridder, seen);
        ++out.layers;
    }
    return out;
}

}  // namespace

std::uint64_t full_layers_peak_bytes(const dataset::Dataset& ds, const DemGrid& grid,
                                     std::span<const GridLayer> layers) {
    double reach = 0, per_texel = 0;
    for (const GridLayer& l : layers) {
        reach = std::max(reach, gridder_reach_m(l.gridder, grid.texel_m));
        per_texel += static_cast<double>(gridder_bytes_per_texel(l.gridder));
    }
    const BlockRange selected = grid.selected_blocks();
    double rows = 0;
    for (const auto& t : ds.tiles) {
        const BlockRange r = tile_blocks(grid, t.bounds_m, reach).intersection(selected);
        if (!r.empty()) rows = std::max(rows, static_cast<double>(r.y1 - r.y0 + 2));
    }
    const double blocks = static_cast<double>(grid.blocks_x()) * grid.blocks_y();
    const double held = std::min(static_cast<double>(selected.count()), rows * (selected.x1 - selected.x0 + 1));
    const double block_texels = static_cast<double>(grid.block) * grid.block;
    const TinPoints tin = tin_point_bytes(ds, grid, layers);
    const double bytes = held * (block_texels * per_texel + tin.layers * kHeldChunkBytes) + tin.held_bytes +
                         tin.finishing_bytes + blocks * sizeof(int) + reading_bytes(ds);
    return bytes >= 1.8e19 ? ~0ull : static_cast<std::uint64_t>(bytes);
}

double held_points_estimate(const dataset::Dataset& ds, const DemGrid& grid, std::span<const GridLayer> layers) {
    double reach = 0, grown = 0;
    for (const GridLayer& l : layers) {
        reach = std::max(reach, gridder_reach_m(l.gridder, grid.texel_m));
        if (is_tin(l)) grown += grown_by_margin(grid, l);
    }
    if (grown == 0) return 0;
    return densest_band_points(ds, grid, held_band_m(ds, grid, reach), reach) * grown;
}

std::uint64_t full_dem_peak_bytes(const dataset::Dataset& ds, const DemGrid& grid, const GridderSpec& gridder,
                                  bool rgb) {
    GridLayer layer{gridder, PointFilter()};
    layer.gridder.rgb = rgb;
    return full_layers_peak_bytes(ds, grid, std::span<const GridLayer>(&layer, 1));
}

std::vector<float> heights_in_file_units(std::span<const float> metres, double z_to_metres, float nodata) {
    std::vector<float> out(metres.size(), nodata);
    for (std::size_t i = 0; i < metres.size(); ++i) {
        if (std::isnan(metres[i])) continue;
        out[i] = z_to_metres == 1.0 ? metres[i] : static_cast<float>(metres[i] / z_to_metres);
    }
    return out;
}

FullDemStats grid_full_layers(const dataset::Dataset& ds, const DemGrid& grid, std::span<const GridLayer> layers,
                              const BlockWriteFn& write, ThreadPool& pool,
                              const std::function<void(std::uint64_t, std::uint64_t)>& progress) {
    if (layers.empty() || layers.size() > 32) throw Error::in_stage("dem", "1 to 32 layers per pass (internal error)");
    FullDemStats stats;
    stats.layer_points.assign(layers.size(), 0);
    BlockSet blocks(grid, layers, write, stats);
    std::vector<BlockRange> ranges(ds.tiles.size());
    std::uint64_t total = 0;
    for (std::size_t i = 0; i < ds.tiles.size(); ++i) {
        ranges[i] = tile_blocks(grid, ds.tiles[i].bounds_m, blocks.reach_m());
        blocks.expect(ranges[i]);
        if (!ranges[i].intersection(grid.selected_blocks()).empty()) total += ds.tiles[i].tile.header.point_count;
    }
    const bool rgb = std::any_of(layers.begin(), layers.end(), [](const GridLayer& l) { return l.gridder.rgb; });
    const std::uint32_t fields = las::fields::kXyz | las::fields::kClassification | las::fields::kReturns |
                                 las::fields::kIntensity | (rgb ? las::fields::kRgb : 0u);
    std::vector<std::uint32_t> order;
    for (const std::uint32_t t : tile_order(ds)) {
        if (!ranges[t].intersection(grid.selected_blocks()).empty()) order.push_back(t);
    }
    std::vector<std::uint64_t> outside(ds.tiles.size(), 0);  // per tile: points beyond its header bounds
    const auto add = [&](std::uint32_t t, std::uint64_t, std::span<const dataset::MetricPoint> points) {
        for (const auto& p : points) {
            std::uint32_t mask = 0;
            for (std::size_t i = 0; i < layers.size(); ++i) {
                if (layers[i].filter.keeps_drawn(p.classification, p.return_kinds, p.intensity)) mask |= 1u << i;
            }
            if (mask == 0) continue;
            const Added a = blocks.add(p, ranges[t], mask);
            if (a == Added::Used) {
                ++stats.points_used;
                for (std::size_t i = 0; mask != 0; ++i, mask >>= 1) stats.layer_points[i] += mask & 1u;
            }
            outside[t] += a == Added::OutsideTile;
        }
        stats.points_read += points.size();
        if (progress) progress(stats.points_read, total);
    };
    const auto skipped = [&](std::uint32_t, const dataset::SkippedChunk& s) {
        stats.skipped.push_back(s.error);
        stats.points_skipped += s.points;
    };
    dataset::for_each_metric_batch(ds, order, pool, add, [&](std::uint32_t t) { blocks.tile_done(ranges[t], pool); },
                                   fields, kReadBatchPoints, skipped);
    for (std::size_t t = 0; t < ds.tiles.size(); ++t) {
        if (outside[t] == 0) continue;
        stats.skipped.push_back({ds.tiles[t].tile.path(), std::nullopt,
                                 std::to_string(outside[t]) + " points lie outside the tile's header bounds (a corrupt "
                                                              "header or chunk?): left out"});
        stats.points_skipped += outside[t];
    }
    return stats;
}

FullDemStats grid_full_dem(const dataset::Dataset& ds, const DemGrid& grid, const FullDemOptions& options,
                           const DemOutputs& outputs, ThreadPool& pool) {
    if (!outputs.heights) throw Error::in_stage("dem", "no height raster to write (internal error)");
    GridLayer layer{options.gridder, options.filter};
    layer.gridder.rgb = outputs.rgb != nullptr;
    const BlockWriteFn write = [&](lidarscout::CellKey c, std::vector<BlockImages>& layers) {
        const BlockImages& images = layers.front();
        write_block(*outputs.heights, grid, 1, c.ix, c.iy,
                    std::span<const float>(heights_in_file_units(images.heights_m, outputs.z_to_metres,
                                                                 options.nodata)));
        if (!outputs.rgb) return;
        const std::size_t plane = images.heights_m.size();
        for (int band = 0; band < 4; ++band) {
            write_block(*outputs.rgb, grid, band + 1, c.ix, c.iy,
                        std::span<const std::uint8_t>(images.rgba.data() + band * plane, plane));
        }
    };
    return grid_full_layers(ds, grid, std::span<const GridLayer>(&layer, 1), write, pool, options.progress);
}

}  // namespace lidarscout::raster
