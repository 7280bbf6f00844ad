// for_each_metric_batch: records -> points in metres with 8-bit colour, tile after tile, the
// next batch decoded and placed on the pool while the caller uses this one.
#include "dataset/point_stream.hpp"

#include <algorithm>
#include <future>
#include <memory>
#include <optional>
#include <vector>

#include "core/error.hpp"
#include "core/thread_pool.hpp"
#include "dataset/chunk_points.hpp"
#include "dataset/dataset.hpp"
#include "dataset/las_colour.hpp"
#include "dataset/overview_sidecar.hpp"
#include "dataset/point_reader.hpp"
#include "io/file.hpp"
#include "las/point_format.hpp"

namespace lidarscout::dataset {

bool tile_colour_is_16bit(const Dataset& ds, std::uint32_t tile) {
    const auto& t = ds.tiles.at(tile);
    const auto samples = read_chunk_points(io::File::open(t.tile.path()), t.tile, ds.las_stride);
    return colour_is_16bit(samples, [](const ChunkPoint& c) {
        return std::max({c.point.rgb[0], c.point.rgb[1], c.point.rgb[2]});
    });
}

namespace {

constexpr std::size_t kPlacePiece = 1u << 15;  // points placed per pool task

// One tile being read: its file, its batches and how its records become MetricPoints.
struct TileReader {
    TileReader(const Dataset& ds, std::uint32_t index, std::uint32_t fields, std::uint64_t batch_points)
        : file(io::File::open(ds.tiles.at(index).tile.path())),
          tile(tile_to_read(ds.tiles.at(index), file, fresh)),
          batches(tile.tile, batch_points),
          placer(tile, has_colour(tile, fields) && tile_colour_is_16bit(ds, index), has_colour(tile, fields)) {}

    static bool has_colour(const DatasetTile& t, std::uint32_t fields) {
        return las::point_format_info(t.tile.header.point_format).rgb_offset >= 0 && (fields & las::fields::kRgb);
    }

    // Records [first, first + out.size()) of `records` into `out`, placed in the dataset's frame.
    void place(std::span<const std::uint8_t> records, std::size_t first, std::span<MetricPoint> out) const {
        placer.place(records, first, out);
    }

    std::optional<DatasetTile> fresh;  // a tile changed since its overview sidecar, read itself
    io::File file;
    const DatasetTile& tile;
    RecordBatches batches;
    RecordPlacer placer;
};

// A batch made ready for the caller.
struct ReadyBatch {
    std::uint32_t tile = 0;
    std::uint64_t first_point = 0;
    bool has_points = false, last_of_tile = false;
    std::vector<std::uint8_t> records;
    std::vector<MetricPoint> points;
    std::vector<SkippedChunk> skipped;  // left out of `points` (only when the walk skips)
};

// Walks the tiles' batches in order; next() makes the next one ready (decoded and placed on the pool).
class MetricBatchWalk {
public:
    MetricBatchWalk(const Dataset& ds, std::span<const std::uint32_t> tiles, ThreadPool& pool, std::uint32_t fields,
                    std::uint64_t batch_points, bool skip)
        : ds_(ds), tiles_(tiles), pool_(pool), fields_(fields), batch_points_(batch_points), skip_(skip) {}

    bool done() const { return position_ >= tiles_.size(); }

    void next(ReadyBatch& out) {
        out.tile = tiles_[position_];
        out.skipped.clear();
        if (!reader_ && !open_reader(out)) return;
        out.has_points = batch_ < reader_->batches.size();
        if (out.has_points) fill(out);
        out.last_of_tile = batch_ + 1 >= reader_->batches.size();
        if (out.last_of_tile) {
            reader_.reset();
            ++position_, batch_ = 0;
        } else {
            ++batch_;
        }
    }

private:
    // Opens the current tile; a tile that cannot be opened is, when skipping, a batch without
    // points that ends the tile.
    bool open_reader(ReadyBatch& out) {
        try {
            reader_ = std::make_unique<TileReader>(ds_, tiles_[position_], fields_, batch_points_);
            return true;
        } catch (const Error& e) {
            if (!skip_) throw;
            out.skipped.push_back({0, ds_.tiles[out.tile].tile.header.point_count, ErrorRecord::of(e)});
            out.has_points = false, out.last_of_tile = true;
            ++position_, batch_ = 0;
            return false;
        }
    }

    void fill(ReadyBatch& out) {
        const TileReader& r = *reader_;
        out.first_point = r.batches.first_point(batch_);
        r.batches.read(r.file, batch_, out.records, fields_, pool_, skip_ ? &out.skipped : nullptr);
        out.points.resize(out.records.size() / r.tile.tile.header.record_length);
        const std::size_t n = out.points.size(), pieces = (n + kPlacePiece - 1) / kPlacePiece;
        pool_.for_each(pieces, [&](std::size_t i) {
            const std::size_t first = i * kPlacePiece;
            const std::size_t count = std::min(kPlacePiece, n - first);
            r.place(out.records, first, std::span<MetricPoint>(out.points).subspan(first, count));
        });
    }

    const Dataset& ds_;
    std::span<const std::uint32_t> tiles_;
    ThreadPool& pool_;
    std::uint32_t fields_;
    std::uint64_t batch_points_;
    bool skip_;
    std::size_t position_ = 0, batch_ = 0;
    std::unique_ptr<TileReader> reader_;
};

}  // namespace

void for_each_metric_batch(const Dataset& ds, std::span<const std::uint32_t> tiles, ThreadPool& pool,
                           const TileMetricBatchFn& fn, const TileDoneFn& tile_done, std::uint32_t fields,
                           std::uint64_t batch_points, const SkippedFn& skipped) {
    MetricBatchWalk walk(ds, tiles, pool, fields, batch_points, skipped != nullptr);
    if (walk.done()) return;
    ReadyBatch ready[2];
    std::future<void> next;  // declared after the batches: destroyed (waited for) first
    walk.next(ready[0]);
    for (std::size_t k = 0;; ++k) {
        const ReadyBatch& b = ready[k % 2];
        ReadyBatch& following = ready[(k + 1) % 2];
        if (!walk.done()) next = std::async(std::launch::async, [&walk, &following] { walk.next(following); });
        for (const auto& s : b.skipped) skipped(b.tile, s);
        if (b.has_points) fn(b.tile, b.first_point, b.points);
        if (b.last_of_tile && tile_done) tile_done(b.tile);
        if (!next.valid()) break;
        next.get();
    }
}

void for_each_metric_batch(const Dataset& ds, std::uint32_t tile, ThreadPool& pool, const MetricBatchFn& fn,
                           std::uint32_t fields) {
    const std::uint32_t tiles[] = {tile};
    const auto one = [&](std::uint32_t, std::uint64_t first, std::span<const MetricPoint> p) { fn(first, p); };
    for_each_metric_batch(ds, tiles, pool, one, nullptr, fields);
}

}  // namespace lidarscout::dataset
