// read_region_points: the tiles touching a region, batch by batch, their points filtered in
// parallel pieces and handed on in file order.
#include "pipelines/region_points.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <memory>
#include <optional>

#include "core/thread_pool.hpp"
#include "dataset/overview_sidecar.hpp"
#include "dataset/point_reader.hpp"
#include "core/polygon.hpp"
#include "geo/geographic.hpp"
#include "io/file.hpp"

namespace lidarscout::pipelines {
namespace {

constexpr std::size_t kPiece = 1u << 15;  // records filtered per pool task

// The kept points of one piece of a batch.
struct Kept {
    std::vector<std::uint8_t> records;
    std::vector<RegionPoint> points;
};

void keep_piece(const dataset::DatasetTile& t, const FrameUnits& units, std::span<const std::uint8_t> records,
                const Region& region, const PointFilter& filter, Kept& out) {
    const auto& header = t.tile.header;
    const auto& format = las::point_format_info(header.point_format);
    const std::size_t length = header.record_length;
    out.records.clear(), out.points.clear();
    for (std::size_t at = 0; at + length <= records.size(); at += length) {
        const auto record = records.subspan(at, length);
        RegionPoint p{0, 0, 0, las::decode_point(record, format, header)};
        if (!filter.keeps(p.point)) continue;
        units(p.point, p.x, p.y, p.z);
        if (!region.contains(p.x, p.y)) continue;
        out.records.insert(out.records.end(), record.begin(), record.end());
        out.points.push_back(p);
    }
}

// Filters one batch's records on the pool and hands the kept ones to fn in file order, a piece at a time.
// The pieces' buffers (`pieces`) are kept from batch to batch: freed, glibc's default thresholds would
// hand them back to the kernel, and every batch would fault in fresh zeroed pages (a page fault per 4 KiB
// kept: 590 K of them reading ky-jmo335 in a Python process, where the CLI's mallopt does not apply).
void keep_batch(const dataset::DatasetTile& t, const FrameUnits& units, std::uint32_t tile,
                std::span<const std::uint8_t> records,
                const Region& region, const PointFilter& filter, ThreadPool& pool, const RegionBatchFn& fn,
                RegionReadStats& stats, std::vector<Kept>& pieces) {
    const std::size_t length = t.tile.header.record_length, n = records.size() / length;
    const std::size_t count = (n + kPiece - 1) / kPiece;
    if (pieces.size() < count) pieces.resize(count);
    pool.for_each(count, [&](std::size_t i) {
        const std::size_t first = i * kPiece, size = std::min(kPiece, n - first);
        keep_piece(t, units, records.subspan(first * length, size * length), region, filter, pieces[i]);
    });
    stats.points_read += n;
    for (std::size_t i = 0; i < count; ++i) {  // each piece as it is (a batch's kept points copied into one
        const Kept& piece = pieces[i];           // would double them)
        stats.points_kept += piece.points.size();
        if (!piece.points.empty()) fn(RegionBatch{tile, piece.records, piece.points});
    }
}

// One tile's batches; an Error opening it, reading a batch (not a chunk: those are skipped alone)
// or placing a point leaves the rest of the tile out.
void read_tile(const dataset::Dataset& ds, std::uint32_t tile, const Region& region,
               const PointFilter& filter, ThreadPool& pool, const RegionBatchFn& fn, RegionReadStats& stats,
               const std::function<void(std::uint64_t)>& advanced, const ReadWatch& watch, std::size_t batch_points,
               std::vector<Kept>& pieces) {
    const auto& placed = ds.tiles[tile];
    std::uint64_t done = 0;
    std::optional<dataset::DatasetTile> fresh;  // (a tile changed since its overview sidecar: read itself)
    const dataset::DatasetTile* tp = &placed;
    try {
        const io::File file = io::File::open(placed.tile.path());
        tp = &dataset::tile_to_read(placed, file, fresh);
        const auto& t = *tp;
        const dataset::RecordBatches batches(t.tile, batch_points);
        const FrameUnits units(t, ds.frame);
        ++stats.tiles_decoded;
        std::vector<std::uint8_t> records;
        std::vector<dataset::SkippedChunk> skipped;
        for (std::size_t k = 0; k < batches.size(); ++k) {
            if (watch.cancelled()) return void(stats.cancelled = true);
            skipped.clear();
            batches.read(file, k, records, las::fields::kAll, pool, &skipped);
            for (const auto& s : skipped) stats.skipped.push_back(s.error), stats.points_skipped += s.points;
            keep_batch(t, units, tile, records, region, filter, pool, fn, stats, pieces);
            done += batches.point_count(k);
            advanced(batches.point_count(k));
        }
    } catch (const Error& e) {
        const auto& t = *tp;
        stats.skipped.push_back(ErrorRecord::of(e.file().empty() ? e.with_file(t.tile.path()) : e));
        stats.points_skipped += t.tile.header.point_count - std::min(done, t.tile.header.point_count);
        advanced(t.tile.header.point_count - std::min(done, t.tile.header.point_count));
    }
}

}  // namespace

Region box_region(double min_x, double min_y, double max_x, double max_y) {
    Region r;
    r.box.min_x = min_x, r.box.min_y = min_y, r.box.max_x = max_x, r.box.max_y = max_y;
    r.box.min_z = -INFINITY, r.box.max_z = INFINITY;
    const dataset::Bounds b = r.box;
    r.contains = [b](double x, double y) { return x >= b.min_x && x <= b.max_x && y >= b.min_y && y <= b.max_y; };
    r.touches = [b](const dataset::Bounds& t) {
        return t.min_x <= b.max_x && t.max_x >= b.min_x && t.min_y <= b.max_y && t.max_y >= b.min_y;
    };
    return r;
}

Region bounds_region(std::span<const double> b, const std::string& stage, const std::string& option) {
    if (b.size() != 4) throw Error(stage + ": " + option + " expects four numbers: xmin,ymin,xmax,ymax");
    if (!(b[0] <= b[2] && b[1] <= b[3])) {
        throw Error(stage + ": " + option + " expects xmin,ymin,xmax,ymax with xmin <= xmax and ymin <= ymax");
    }
    if (b[0] == b[2] || b[1] == b[3]) {
        throw Error(stage + ": " + option + " enclose no area (xmin = xmax or ymin = ymax); nothing written");
    }
    return box_region(b[0], b[1], b[2], b[3]);
}

Region polygon_region(MultiPolygon polygon) {
    const auto shape = std::make_shared<const MultiPolygon>(std::move(polygon));
    Region r = box_region(shape->min_x(), shape->min_y(), shape->max_x(), shape->max_y());
    r.contains = [shape](double x, double y) { return shape->contains(x, y); };
    r.touches = [shape](const dataset::Bounds& t) { return shape->touches_box(t.min_x, t.min_y, t.max_x, t.max_y); };
    return r;
}

std::vector<std::uint32_t> tiles_touching(const dataset::Dataset& ds, const Region& region) {
    std::vector<std::uint32_t> out;
    const double f = ds.frame.xy_to_metres;
    for (std::uint32_t i = 0; i < ds.tiles.size(); ++i) {
        const auto& m = ds.tiles[i].bounds_m;
        if (m.empty()) continue;
        dataset::Bounds b = m;
        b.min_x /= f, b.min_y /= f, b.max_x /= f, b.max_y /= f;
        if (region.touches(b)) out.push_back(i);
    }
    if (!ds.placed) return out;
    dataset::ensure_tiles(ds, out);  // (a placed dataset's, as the viewer holds it: their headers first)
    std::erase_if(out, [&](std::uint32_t i) { return !ds.is_ready(i); });
    return out;
}

RegionReadStats read_region_points(const dataset::Dataset& ds, std::span<const std::uint32_t> tiles,
                                   const Region& region, const PointFilter& filter, ThreadPool& pool,
                                   const RegionBatchFn& fn, const ReadWatch& watch, std::size_t batch_points) {
    RegionReadStats stats;
    stats.tiles_touched.assign(tiles.begin(), tiles.end());
    std::uint64_t total = 0, done = 0;
    for (const auto t : tiles) total += ds.tiles[t].tile.header.point_count;
    const auto advanced = [&](std::uint64_t n) {
        done += n;
        if (watch.progress) watch.progress(done, total);
    };
    std::vector<Kept> pieces;  // (keep_batch's buffers, for every batch of every tile)
    for (std::size_t k = 0; k < tiles.size() && !stats.cancelled; ++k) {
        if (watch.cancelled()) stats.cancelled = true;
        else read_tile(ds, tiles[k], region, filter, pool, fn, stats, advanced, watch, batch_points, pieces);
        if (watch.tiles && !stats.cancelled) watch.tiles(k + 1, tiles.size());
    }
    return stats;
}

void require_touched_tiles(const dataset::Dataset& ds, std::span<const std::uint32_t> tiles, const Region& region,
                           const std::string& stage, const std::string& where) {
    if (!tiles.empty()) return;
    const auto& a = region.box;
    const auto& b = ds.bounds_m;
    const double f = ds.frame.xy_to_metres;
    std::string hint;
    if (ds.frame.geographic && !geo::looks_like_degrees(a.min_x, a.min_y, a.max_x, a.max_y)) {
        const geo::UtmZone zone = geo::utm_zone_at(b.centre_x(), b.centre_y());
        hint = fmt::format("; the data is in degrees (longitude, latitude): give {} in degrees, or in metres with "
                           "--crs {} ({})", where, zone.crs, zone.name);
    } else if (!ds.frame.geographic && geo::looks_like_degrees(a.min_x, a.min_y, a.max_x, a.max_y)) {
        hint = fmt::format("; {} is given in the CRS's units ({}), not in degrees", where,
                           ds.frame.crs.empty() ? "no CRS named" : ds.frame.crs);
    }
    throw Error::in_stage(stage, fmt::format("no tile touches {} ({:.10g}, {:.10g}) - ({:.10g}, {:.10g}); the data "
                                             "covers ({:.3f}, {:.3f}) - ({:.3f}, {:.3f}) in its CRS's units{}; "
                                             "nothing written",
                                             where, a.min_x, a.min_y, a.max_x, a.max_y, b.min_x / f, b.min_y / f,
                                             b.max_x / f, b.max_y / f, hint));
}

void require_kept_points(const dataset::Dataset& ds, std::span<const std::uint32_t> tiles, const Region& region,
                         const PointFilter& filter, const RegionReadStats& stats, ThreadPool& pool,
                         const std::string& stage, const std::string& where) {
    if (stats.points_kept > 0 || stats.cancelled) return;
    const std::string unread = stats.points_skipped == 0 ? "" : fmt::format(
        "; {} points could not be read", fmt::group_digits(stats.points_skipped));
    const std::uint64_t inside = filter.keeps_everything() ? 0 : read_region_points(
        ds, tiles, region, PointFilter(), pool, [](const RegionBatch&) {}).points_kept;
    if (inside == 0) {
        const char* tile_word = tiles.size() == 1 ? "tile" : "tiles";
        throw Error::in_stage(stage, fmt::format("no point lies in {}: none of the {} points of the {} {} it "
                                                 "touches{}; nothing written", where,
                                                 fmt::group_digits(stats.points_read), tiles.size(), tile_word,
                                                 unread));
    }
    throw Error::in_stage(stage, fmt::format("no point of {} in {} ({} points in it{}); nothing written: leave out "
                                             "--classes, --returns, --intensity or choose others",
                                             filter.describe(), where, fmt::group_digits(inside), unread));
}

}  // namespace lidarscout::pipelines
