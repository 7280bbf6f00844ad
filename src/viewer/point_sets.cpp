// Point sets: grid cells' chunk points and tiles' decoded points as render batches.
#include "viewer/point_sets.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <optional>
#include <unordered_map>

#include "dataset/chunk_points.hpp"
#include "dataset/overview_sidecar.hpp"
#include "dataset/las_colour.hpp"
#include "dataset/point_reader.hpp"
#include "io/file.hpp"
#include "las/point_fields.hpp"
#include "las/point_format.hpp"

namespace lidarscout::viewer {
namespace {

constexpr std::size_t kConvertBlock = 16384;  // records converted per pool task

bool colour_is_16bit(std::span<const dataset::ChunkPoint> samples) {
    return dataset::colour_is_16bit(samples, [](const dataset::ChunkPoint& c) {
        return std::max({c.point.rgb[0], c.point.rgb[1], c.point.rgb[2]});
    });
}

// What converting a tile's records needs, fixed per tile.
// Records of one tile to PointAttrs relative to a set's origin, through the dataset's one
// record conversion (dataset::RecordPlacer).
struct RecordConverter {
    dataset::RecordPlacer placer;
    double origin_x, origin_y, origin_z;
    std::size_t record_length;
};

RecordConverter converter(const dataset::DatasetTile& tile, const PointSet& set,
                          std::span<const dataset::ChunkPoint> samples) {
    return {dataset::RecordPlacer(tile, colour_is_16bit(samples)), set.origin_x, set.origin_y, set.origin_z,
            tile.tile.header.record_length};
}

PointSet empty_tile_set(const dataset::DatasetTile& tile) {
    PointSet set;
    set.origin_x = tile.bounds_m.min_x, set.origin_y = tile.bounds_m.min_y, set.origin_z = tile.bounds_m.min_z;
    const double spacing = mean_point_spacing(tile);
    set.spacing_m = std::isfinite(spacing) ? static_cast<float>(spacing) : 0.0f;
    return set;
}

// Converts `records` (record_length each) into `out` (as many points).
void convert_records(std::span<const std::uint8_t> records, std::span<render::PointAttr> out,
                     const RecordConverter& convert) {
    std::vector<dataset::MetricPoint> points(out.size());
    convert.placer.place(records, 0, points);
    for (std::size_t k = 0; k < out.size(); ++k) {
        const dataset::MetricPoint& p = points[k];
        render::PointAttr& a = out[k];
        a.dx = static_cast<float>(p.x - convert.origin_x);
        a.dy = static_cast<float>(p.y - convert.origin_y);
        a.dz = static_cast<float>(p.z - convert.origin_z);
        a.r = p.rgb.r, a.g = p.rgb.g, a.b = p.rgb.b;
        a.classification = p.classification;
        a.intensity = p.intensity;
        a.returns = p.return_kinds;
    }
}

// Converts `records` (record_length each) and appends them to `set`, in blocks on `pool`.
void append_records(PointSet& set, std::span<const std::uint8_t> records, const RecordConverter& convert,
                    ThreadPool& pool) {
    const std::size_t record = convert.record_length;
    const std::size_t n = records.size() / record, first = set.points.size();
    set.points.resize(first + n);
    pool.for_each_block(n, kConvertBlock, [&](std::size_t begin, std::size_t end) {
        convert_records(records.subspan(begin * record, (end - begin) * record),
                        std::span(set.points).subspan(first + begin, end - begin), convert);
    });
}

constexpr std::uint32_t kDrawnFields = las::fields::kXyz | las::fields::kIntensity | las::fields::kClassification |
                                       las::fields::kRgb | las::fields::kReturns;

// The order key of each decode unit: `order` at the middle of its chunk point and the next
// unit's (its own alone for the last); +infinity without a chunk point.
std::vector<double> unit_keys(const dataset::DatasetTile& tile, const dataset::DecodeUnits& units,
                              std::span<const dataset::ChunkPoint> samples, const PointOrder& order) {
    std::unordered_map<std::uint64_t, const las::Point*> at;
    for (const auto& c : samples) at.emplace(c.index, &c.point);
    const auto find = [&](std::size_t u) -> const las::Point* {
        if (u >= units.size()) return nullptr;
        const auto it = at.find(units.first_point(u));
        return it == at.end() ? nullptr : it->second;
    };
    std::vector<double> keys(units.size(), std::numeric_limits<double>::infinity());
    for (std::size_t u = 0; u < units.size(); ++u) {
        const las::Point* a = find(u);
        if (!a) continue;
        const las::Point* b = find(u + 1) ? find(u + 1) : a;
        double x = 0.5 * (a->x + b->x), y = 0.5 * (a->y + b->y), z = 0.5 * (a->z + b->z);
        tile.place(x, y, z);
        keys[u] = order(x, y, z);
    }
    return keys;
}

// Decodes the units `units` (any order) into one point set: each unit converted right after it is
// decoded, while its records are in cache, by the thread that decoded it.
PointSet decode_piece(const io::File& file, const dataset::DecodeUnits& all, std::span<const std::size_t> units,
                      const dataset::DatasetTile& tile, const RecordConverter& convert, ThreadPool& pool) {
    const std::size_t record = tile.tile.header.record_length;
    std::vector<std::uint64_t> first(units.size() + 1, 0);  // each unit's first point in the set
    for (std::size_t k = 0; k < units.size(); ++k) first[k + 1] = first[k] + all.point_count(units[k]);
    PointSet set = empty_tile_set(tile);
    set.points.resize(first.back());
    // A remote tile's units are fetched together (one request where they lie close), not one round trip each.
    std::vector<std::vector<std::uint8_t>> fetched;
    if (file.remote()) {
        std::vector<std::pair<std::uint64_t, std::uint64_t>> ranges;
        for (const std::size_t u : units) ranges.emplace_back(all.byte_offset(u), all.byte_size(u));
        fetched = file.read_ranges(ranges, "LAZ chunk");
    }
    pool.for_each(units.size(), [&](std::size_t k) {
        std::vector<std::uint8_t> scratch, records((first[k + 1] - first[k]) * record);
        if (fetched.empty()) all.decode(file, units[k], records, kDrawnFields, scratch);
        else all.decode_bytes(file.path(), units[k], fetched[k], records, kDrawnFields);
        convert_records(records, std::span(set.points).subspan(first[k], first[k + 1] - first[k]), convert);
    });
    return set;
}

// Where each piece starts in `units` (and the end): about `piece_points` points each (whole
// units), as many as fit in `max_points` (at least one).
std::vector<std::size_t> cut_pieces(const dataset::DecodeUnits& all, std::span<const std::size_t> units,
                                    std::uint64_t piece_points, std::uint64_t max_points) {
    std::vector<std::size_t> starts{0};
    std::uint64_t total = 0;
    for (std::size_t first = 0; first < units.size();) {
        std::size_t last = first;
        std::uint64_t points = 0;
        for (; last < units.size() && (last == first || points < piece_points); ++last) {
            points += all.point_count(units[last]);
        }
        total += points;
        if (first > 0 && total > max_points) break;
        starts.push_back(last);
        first = last;
    }
    return starts;
}

}  // namespace

double mean_point_spacing(const dataset::DatasetTile& tile) {
    const auto& b = tile.bounds_m;
    const double area = b.empty() ? 1.0 : std::max((b.max_x - b.min_x) * (b.max_y - b.min_y), 1.0);
    const auto n = tile.points;
    return n ? std::sqrt(area / static_cast<double>(n)) : std::numeric_limits<double>::infinity();
}

std::vector<render::PointBatch> batches_of(std::span<const PointSet> sets) {
    std::vector<render::PointBatch> out;
    out.reserve(sets.size());
    for (const auto& s : sets) out.push_back(s.batch());
    return out;
}

std::uint64_t point_count(std::span<const PointSet> sets) {
    std::uint64_t n = 0;
    for (const auto& s : sets) n += s.points.size();
    return n;
}

void count_classes(PointSet& set) {
    std::array<std::uint32_t, 256> counts{};
    for (const auto& p : set.points) ++counts[p.classification];
    set.class_counts.clear();
    for (std::size_t c = 0; c < counts.size(); ++c) {
        if (counts[c]) set.class_counts.emplace_back(static_cast<std::uint8_t>(c), counts[c]);
    }
}

PointSet cell_point_set(const lidarscout::PatchGrid& grid, lidarscout::CellKey cell) {
    PointSet set;
    set.origin_x = grid.cell_min_x(cell);
    set.origin_y = grid.cell_min_y(cell);
    grid.read_points(cell, [&](std::span<const GridPoint> points) {  // (converted in place: no copy first)
        set.points.resize(points.size());
        for (std::size_t i = 0; i < points.size(); ++i) set.points[i] = chunk_point_attr(points[i], 0, 0);
    });
    return set;
}

render::PointAttr chunk_point_attr(const GridPoint& p, float dx, float dy) {
    render::PointAttr a;
    a.dx = p.dx + dx, a.dy = p.dy + dy, a.dz = p.z;
    a.r = p.rgb.r, a.g = p.rgb.g, a.b = p.rgb.b;
    a.classification = p.classification;
    a.intensity = p.intensity;
    return a;
}

void paint_uncoloured(std::span<PointSet> sets) {
    for (auto& s : sets) {
        for (auto& p : s.points) p.r = p.g = p.b = kUncolouredGrey;
    }
}

bool survey_has_rgb(const dataset::Dataset& ds) {
    const auto rgb = [](const dataset::DatasetTile& t) {
        return las::point_format_info(t.tile.header.point_format).rgb_offset >= 0;
    };
    if (ds.placed) {  // headers read on demand: the first tile that can be read speaks for the survey
        for (std::size_t i = 0; i < std::min<std::size_t>(ds.tiles.size(), 8); ++i) {
            if (ds.ready(i)) return rgb(ds.tiles[i]);
        }
        return false;
    }
    std::size_t with = 0;
    for (const auto& t : ds.tiles) with += rgb(t);
    return with > 0 && with * 2 >= ds.tiles.size();
}

std::uint64_t tile_point_set_bytes(const dataset::DatasetTile& tile) {
    return tile.points * sizeof(render::PointAttr);
}

// The records of `records` that `filter` keeps, back to back in `kept`.
// Drops from set.points[first, end) the points `filter` does not keep: their attributes say enough,
// no record is decoded a second time.
void drop_filtered(PointSet& set, std::size_t first, const PointFilter& filter) {
    const auto dropped = [&](const render::PointAttr& a) {
        return !filter.keeps_drawn(a.classification, a.returns, a.intensity);
    };
    const auto from = set.points.begin() + static_cast<std::ptrdiff_t>(first);
    set.points.erase(std::remove_if(from, set.points.end(), dropped), set.points.end());
}

PointSet tile_point_set(const dataset::DatasetTile& placed, std::uint64_t las_stride, ThreadPool& pool,
                        const std::function<void(std::uint64_t)>& progress,
                        std::vector<dataset::SkippedChunk>* skipped, const PointFilter* filter) {
    if (filter && filter->keeps_everything()) filter = nullptr;
    const auto file = io::File::open(placed.tile.path());
    std::optional<dataset::DatasetTile> fresh;  // (a tile changed since its overview sidecar: read itself)
    const dataset::DatasetTile& tile = dataset::tile_to_read(placed, file, fresh);
    PointSet set = empty_tile_set(tile);
    const auto samples = dataset::read_chunk_points(file, tile.tile, las_stride);
    const RecordConverter convert = converter(tile, set, samples);
    set.points.reserve(tile.tile.header.point_count);
    dataset::for_each_record_batch(
        file, tile.tile, pool,
        [&](std::uint64_t, std::span<const std::uint8_t> records) {
            const std::size_t first = set.points.size();
            append_records(set, records, convert, pool);
            if (filter) drop_filtered(set, first, *filter);
            if (progress) progress(records.size() / tile.tile.header.record_length);
        },
        kDrawnFields, 1u << 20, false, skipped);
    return set;
}

void decode_tile_pieces(const dataset::DatasetTile& placed, std::uint64_t las_stride, ThreadPool& pool,
                        const PointOrder& order, std::uint64_t piece_points, std::uint64_t max_points,
                        const std::function<void(PointSet&&)>& on_piece) {
    const auto file = io::File::open(placed.tile.path());
    std::optional<dataset::DatasetTile> fresh;  // (a tile changed since its overview sidecar: read itself)
    const dataset::DatasetTile& tile = dataset::tile_to_read(placed, file, fresh);
    if (!tile.tile.compressed() || !tile.tile.chunks() || !tile.tile.laz()) {
        on_piece(tile_point_set(tile, las_stride, pool));
        return;
    }
    const dataset::DecodeUnits all(tile.tile);
    const auto samples = dataset::read_chunk_points(file, tile.tile, las_stride);
    const RecordConverter convert = converter(tile, empty_tile_set(tile), samples);
    const std::vector<double> keys = unit_keys(tile, all, samples, order);
    std::vector<std::size_t> units(all.size());
    for (std::size_t u = 0; u < units.size(); ++u) units[u] = u;
    std::stable_sort(units.begin(), units.end(), [&](std::size_t a, std::size_t b) { return keys[a] < keys[b]; });
    const auto pieces = cut_pieces(all, units, piece_points, max_points);
    // One piece per thread rather than every thread on one piece: no thread waits for the
    // slowest chunk of a piece, and a piece's blocks are built while the next one decodes.
    pool.for_each(pieces.size() - 1, [&](std::size_t i) {
        const auto piece = std::span(units).subspan(pieces[i], pieces[i + 1] - pieces[i]);
        on_piece(decode_piece(file, all, piece, tile, convert, pool));
    });
}

}  // namespace lidarscout::viewer
