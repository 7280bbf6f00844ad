// ChunkPointLoader: the read source that takes the tile nearest to the focus next (a tile index
// over the tiles' positions: no sort of every tile when the focus moves), opens files as their
// turn comes, buffers each tile's chunk points and bins them into the grid when the tile is
// complete. Only the tiles being read hold state.
#include "dataset/chunk_point_loader.hpp"

#include <algorithm>
#include <condition_variable>
#include <cerrno>
#include <cmath>
#include <cstring>
#include <future>
#include <optional>
#include <stdexcept>
#include <thread>
#include <unordered_map>

#include "core/error.hpp"
#include "core/patch_grid.hpp"
#include "core/process_memory.hpp"
#include "core/radix_sort.hpp"
#include "core/thread_pool.hpp"
#include "dataset/chunk_points.hpp"
#include "dataset/dataset.hpp"
#include "dataset/las_colour.hpp"
#include "dataset/overview_sidecar.hpp"
#include "dataset/point_reader.hpp"
#include "dataset/tile_index.hpp"
#include "io/file.hpp"
#include "las/point_format.hpp"

namespace lidarscout::dataset {
namespace {

// A chunk point decoded, waiting for the rest of its tile (its colour depth is the tile's).
struct PendingPoint {
    las::Point point;
    std::uint64_t offset = 0;  // of its record, for an error
};

struct TileState {
    std::vector<ChunkPointLocation> locations;  // filled when the tile becomes active
    std::size_t next = 0;                       // next location to hand out
    std::size_t outstanding = 0;                // handed out, not yet completed
    io::ReadTarget target;                      // open while the tile is active
    std::vector<PendingPoint> points;
    std::vector<std::uint8_t> records;  // the raw records, when kept (ChunkPointLoaderOptions::on_tile_records)
    bool whole = true;                  // no read of it failed
};

// Points outside the header bounds by more than this (relative to the tile's extent, plus
// one file unit) are taken as signs of a corrupt chunk table, not drawn.
constexpr double kBoundsTolerance = 0.01;

bool inside_bounds(const DatasetTile& t, const las::Point& p) {
    const auto& h = t.tile.header;
    const double v[3] = {p.x, p.y, p.z};
    for (int a = 0; a < 3; ++a) {
        const double tolerance = kBoundsTolerance * (h.max[a] - h.min[a]) + 1.0;
        if (!(v[a] >= h.min[a] - tolerance && v[a] <= h.max[a] + tolerance)) return false;
    }
    return true;
}

}  // namespace

class ChunkPointLoader::Source final : public io::ReadSource {
public:
    Source(ChunkPointLoader& loader, const Dataset& ds, PatchGrid& grid, bool direct, std::size_t max_errors)
        : loader_(loader), ds_(ds), grid_(grid), direct_(direct), max_errors_(max_errors), index_(ds) {
        if (ds.placed) unread_ = TileIndex(ds);
        for (std::uint32_t i = 0; i < ds.tiles.size(); ++i) {
            if (ds.tiles[i].chunk_points == 0) continue;
            if (!ds.is_ready(i)) unread_.set_pending(i, true);  // (a placed tile always has bounds)
            else if (overview_holds(ds.tiles[i].tile, ds.tiles[i].chunk_points)) held_.push_back(i);
            else if (ds.tiles[i].bounds_m.empty()) unplaced_.push_back(i);
            else index_.set_pending(i, true);
        }
        headers_done_ = unread_.pending_count() == 0;
        std::reverse(unplaced_.begin(), unplaced_.end());  // back = the first
    }
    ~Source() override {
        for (auto& [id, t] : tiles_) t.target = {};
    }

    // Not under the reads' lock: a frame that moves the focus must not wait for files being opened.
    void set_focus(double x, double y) {
        std::lock_guard lock(focus_mutex_);
        focus_ = {x, y};
    }
    void cancel() {
        {
            std::lock_guard lock(mutex_);
            cancelled_ = true;
        }
        headers_cv_.notify_all();
    }

    // A placed dataset's headers, nearest to the focus first, in batches that grow (the first few tiles
    // quickly, then many requests in flight), the next batch's requests sent while one is read; the tiles
    // read join the tiles the reads take kJoin at a time, as their headers come (not when a batch's last
    // one came: the reads would run dry while a 2,048-tile batch's headers arrive).
    void read_headers(unsigned threads) {
        constexpr std::size_t kJoin = 64;
        try {
            std::size_t batch = 16;
            for (std::vector<std::uint32_t> ids = nearest_unread(batch); !ids.empty();) {
                batch = std::min<std::size_t>(batch * 2, 2048);
                std::vector<std::uint32_t> next = nearest_unread(batch);
                std::vector<std::string> paths;  // (the batch's own first: the first batch was not asked yet)
                for (const auto* batch_ids : {&ids, &next}) {
                    for (const std::uint32_t id : *batch_ids) paths.push_back(ds_.path(id));
                }
                io::File::prefetch(paths);
                for (std::size_t at = 0; at < ids.size(); at += kJoin) {
                    const auto part = std::span<const std::uint32_t>(ids).subspan(at, std::min(kJoin, ids.size() - at));
                    ensure_tiles(ds_, part, threads);
                    headers_read(part);
                }
                ids = std::move(next);
            }
        } catch (...) {
            end_headers();
            throw;
        }
        end_headers();
    }
    bool reads_headers() const { return !headers_done_; }

    // Waits until tiles whose headers are read wait for their reads (true), or none will come (false:
    // every header read and its tile read, or a cancel).
    bool more_tiles() {
        std::unique_lock lock(mutex_);
        const auto waiting = [&] { return index_.pending_count() > 0 || !unplaced_.empty(); };
        headers_cv_.wait(lock, [&] { return cancelled_ || headers_done_ || waiting(); });
        return !cancelled_ && waiting();
    }
    void set_on_tile_done(ChunkPointLoader::TileDoneFn f) { on_tile_done_ = std::move(f); }
    std::vector<ErrorRecord> errors() const {
        std::lock_guard lock(mutex_);
        return errors_;
    }

    // (Never waits for a header: the batch reads' callers may hold locks the header reads need. The reads
    // end when no tile with its header read waits; run() starts them again as headers come.)
    std::size_t next(std::span<io::ReadRequest> out) override {
        std::lock_guard lock(mutex_);
        if (cancelled_) return 0;
        const auto [x, y] = focus();
        std::size_t n = 0;
        while (n < out.size()) {
            if (active_.empty() && !start_next(x, y)) break;
            const std::uint32_t id = active_.front();
            TileState& t = tiles_.at(id);
            while (n < out.size() && t.next < t.locations.size()) {
                const auto& at = t.locations[t.next];
                out[n++] = t.target.request(at.offset, ds_.tiles[id].tile.header.record_length,
                                            (std::uint64_t{id} << 32) | t.next);
                ++t.next;
                ++t.outstanding;
            }
            if (t.next == t.locations.size()) active_.erase(active_.begin());
        }
        return n;
    }

    void complete(const io::ReadRequest& r, std::span<const std::uint8_t> data, const ErrorRecord* error) override {
        const auto id = static_cast<std::uint32_t>(r.tag >> 32);
        const auto& tile = ds_.tiles[id];
        std::optional<PendingPoint> point;
        if (!error) {
            point = convert(tile, data, r.offset);
        } else {
            fail(error->file.empty() ? tile.tile.path() : error->file, error->offset.value_or(r.offset), error->cause);
        }
        std::vector<PendingPoint> finished;
        std::vector<std::uint8_t> records;
        {
            std::lock_guard lock(mutex_);
            TileState& t = tiles_.at(id);
            if (point) t.points.push_back(*point);
            keep_record(t, r, data, error != nullptr);
            --t.outstanding;
            if (t.outstanding > 0 || t.next < t.locations.size()) return;
            finished.swap(t.points);
            if (t.whole) records.swap(t.records);
            tiles_.erase(id);
        }
        // (its records kept before it counts as done: a keeper that stops keeping once every tile is done, as the
        // viewer's overview cache does, had lost the last tile's under load, and its next open read that tile)
        if (!records.empty()) loader_.options_.on_tile_records(id, std::move(records));
        publish(id, finished);
    }

    // The tiles whose chunk points an overview sidecar holds, nearest to the focus first, from its
    // records (no read); with `release`, each block of records goes once its tiles' are published
    // (ChunkPointLoaderOptions::release_overview).
    void publish_held(bool release) {
        // (a sidecar whose points are still being decoded is waited for here, on the loader's thread: the dataset
        // opened meanwhile; a tile whose records did not come is read as any other)
        std::erase_if(held_, [&](std::uint32_t id) {
            if (!overview_records(ds_.tiles[id].tile, ds_.tiles[id].chunk_points).empty()) return false;
            std::lock_guard lock(mutex_);
            index_.set_pending(id, true);
            return true;
        });
        const auto [x, y] = focus();
        std::vector<std::pair<double, std::uint32_t>> by_distance;  // (each distance once: a country's are 150,000)
        by_distance.reserve(held_.size());
        for (const std::uint32_t id : held_) by_distance.emplace_back(ds_.tiles[id].bounds_m.distance_xy(x, y), id);
        std::sort(by_distance.begin(), by_distance.end());  // (ties by id: the order they were held in)
        for (std::size_t k = 0; k < held_.size(); ++k) held_[k] = by_distance[k].second;
        by_distance = {};
        std::optional<OverviewRelease> releasing;
        if (release) releasing.emplace(ds_.tiles, held_);
        // The tiles go into the grid in batches: one lookup of a cell and one callback for all a batch's points in
        // it, not one for each tile's (the nearest first, alone; then batches twice as large, up to kMostPoints).
        // A batch's tiles' points are decoded and placed by the shared pool's threads, each tile's on its own,
        // while the batch before goes into the grid on this thread, in the tiles' order (the grid's and the
        // callback's work is this thread's alone: it had waited for each batch's placing, and had placed too).
        // (2^18: a country's 5.4 M sidecar points in 38 batches; in 98 of 2^16, its chunk points took 0.3 s longer
        // after the open, four alternating runs; 2^20, 25 batches, gained nothing more and peaked 20-40 MB higher)
        constexpr std::size_t kMostPoints = 1u << 18;
        std::vector<std::span<const std::uint32_t>> batches;
        for (std::size_t first = 0, batch_points = 1; first < held_.size();) {
            std::size_t end = first, points = 0;
            while (end < held_.size() && (end == first || points < batch_points)) {
                points += ds_.tiles[held_[end++]].chunk_points;
            }
            batches.emplace_back(held_.data() + first, end - first);
            batch_points = std::min(2 * batch_points, kMostPoints);
            first = end;
        }
        using Placed = std::vector<std::pair<CellKey, GridPoint>>;
        const auto place_batch = [this](std::span<const std::uint32_t> batch) {
            std::vector<Placed> per_tile(batch.size());
            ThreadPool::shared().for_each(batch.size(), [&](std::size_t k) { place_held(batch[k], per_tile[k]); });
            Placed placed;
            std::size_t n = 0;
            for (const auto& tile_placed : per_tile) n += tile_placed.size();
            placed.reserve(n);
            for (const auto& tile_placed : per_tile) {
                placed.insert(placed.end(), tile_placed.begin(), tile_placed.end());
            }
            return placed;
        };
        std::future<Placed> next;
        if (!batches.empty()) next = std::async(std::launch::async, place_batch, batches[0]);
        for (std::size_t b = 0; b < batches.size(); ++b) {
            Placed placed = next.get();
            if (is_cancelled()) return;
            if (b + 1 < batches.size()) next = std::async(std::launch::async, place_batch, batches[b + 1]);
            add_placed(batches[b], placed);
            if (releasing) {
                for (const std::uint32_t id : batches[b]) releasing->taken(ds_.tiles[id].tile);
            }
        }
        if (releasing && !held_.empty()) trim_heap();  // the blocks' pages the grid did not take leave the process
        held_ = {};
    }

    // The chunk points an overview sidecar holds for tile `id`, decoded and placed into `placed` (what cannot be is
    // its errors). Safe on several threads at once.
    void place_held(std::uint32_t id, std::vector<std::pair<CellKey, GridPoint>>& placed) {
        const auto& tile = ds_.tiles[id];
        const auto records = overview_records(tile.tile, tile.chunk_points);
        const auto locations = chunk_point_locations(tile.tile, ds_.las_stride);
        const std::size_t length = tile.tile.header.record_length;
        std::vector<PendingPoint> points;
        points.reserve(locations.size());
        for (std::size_t k = 0; k < locations.size() && (k + 1) * length <= records.size(); ++k) {
            auto p = convert(tile, records.subspan(k * length, length), locations[k].offset);
            if (p) points.push_back(*p);
        }
        place(id, points, placed);
    }

private:
    // Up to `most` unread tiles nearest to the focus, taken from the unread ones.
    std::vector<std::uint32_t> nearest_unread(std::size_t most) {
        const auto [x, y] = focus();
        std::vector<std::uint32_t> ids;
        std::lock_guard lock(mutex_);
        if (cancelled_) return ids;
        ids = unread_.nearest_pending(x, y, most);
        for (const std::uint32_t id : ids) unread_.set_pending(id, false);
        return ids;
    }

    // The tiles `ids` whose headers were asked for: each read joins the pending tiles, each that could
    // not be read is an error (its estimated chunk points leave the total).
    void headers_read(std::span<const std::uint32_t> ids) {
        {
            std::lock_guard lock(mutex_);
            for (const std::uint32_t id : ids) {
                if (ds_.is_ready(id)) {
                    index_.set_pending(id, true);
                    upcoming_.clear();  // (it may be nearer than those found)
                    continue;
                }
                loader_.total_ -= ds_.tiles[id].chunk_points;
                record_error({"", std::nullopt, ds_.ready_error(id)});
            }
        }
        headers_cv_.notify_all();
    }

    void end_headers() {
        {
            std::lock_guard lock(mutex_);
            headers_done_ = true;
        }
        headers_cv_.notify_all();
    }

    bool is_cancelled() const {
        std::lock_guard lock(mutex_);
        return cancelled_;
    }

    std::pair<double, double> focus() const {
        std::lock_guard lock(focus_mutex_);
        return focus_;
    }

    // Starts the next tile: tiles without bounds first, then the one nearest to (x, y). False
    // when none is left.
    bool start_next(double x, double y) {
        while (true) {
            std::optional<std::uint32_t> id;
            if (!unplaced_.empty()) {
                id = unplaced_.back();
                unplaced_.pop_back();
            } else {
                id = next_nearest(x, y);
                if (!id) return false;
                index_.set_pending(*id, false);
            }
            if (activate(*id)) return true;
        }
    }

    // The pending tile nearest to (x, y), from the few found nearest at once (kept while the focus stays and no
    // tile joins the pending ones: each search passes the ring of tiles done, a country's hundreds of cells).
    std::optional<std::uint32_t> next_nearest(double x, double y) {
        constexpr std::size_t kFoundAtOnce = 32;
        if (upcoming_focus_ != std::pair{x, y}) upcoming_.clear();
        if (upcoming_.empty()) {
            upcoming_ = index_.nearest_pending(x, y, kFoundAtOnce);
            std::reverse(upcoming_.begin(), upcoming_.end());
            upcoming_focus_ = {x, y};
        }
        if (upcoming_.empty()) return std::nullopt;
        const std::uint32_t id = upcoming_.back();
        upcoming_.pop_back();
        return id;
    }

    // Opens the tile's file and lists its chunk points (it joins the active tiles); false (with an
    // error) when it cannot.
    bool activate(std::uint32_t id) {
        TileState t;
        const auto& tile = ds_.tiles[id];
        try {
            t.locations = chunk_point_locations(tile.tile, ds_.las_stride);
        } catch (const Error& e) {
            record_error(ErrorRecord::of(e));
            loader_.failed_ += tile.chunk_points;
            return false;
        }
        if (ds_.placed) loader_.total_ += t.locations.size() - tile.chunk_points;  // the estimate made exact
        try {
            t.target = io::ReadTarget::open(tile.tile.path(), direct_);
        } catch (const Error& e) {
            record_error(ErrorRecord::of(e));
            loader_.failed_ += t.locations.size();
            return false;
        }
        if (t.locations.empty()) return false;
        if (loader_.options_.on_tile_records) t.records.resize(t.locations.size() * tile.tile.header.record_length);
        tiles_.emplace(id, std::move(t));
        active_.push_back(id);
        return true;
    }

    // The raw record of read `r` into its tile's kept records (when kept; under mutex_).
    void keep_record(TileState& t, const io::ReadRequest& r, std::span<const std::uint8_t> data, bool failed) {
        if (t.records.empty()) return;
        const std::size_t length = t.records.size() / t.locations.size();
        const std::size_t k = r.tag & 0xffffffffu;
        if (failed || data.size() != length || k >= t.locations.size()) {
            t.whole = false;
            return;
        }
        std::copy(data.begin(), data.end(), t.records.begin() + static_cast<std::ptrdiff_t>(k * length));
    }

    std::optional<PendingPoint> convert(const DatasetTile& tile, std::span<const std::uint8_t> data,
                                        std::uint64_t offset) {
        const auto& h = tile.tile.header;
        const las::Point p = las::decode_point(data, las::point_format_info(h.point_format), h);
        if (!inside_bounds(tile, p)) {
            fail(tile.tile.path(), offset,
                 "chunk point lies outside the header bounds (corrupt chunk table?); not drawn");
            return std::nullopt;
        }
        return PendingPoint{p, offset};
    }

    void fail(const std::string& path, std::uint64_t offset, const std::string& cause) {
        ++loader_.failed_;
        std::lock_guard lock(mutex_);
        record_error({path, offset, cause});
    }

    void record_error(ErrorRecord error) {
        if (errors_.size() < max_errors_) errors_.push_back(std::move(error));
    }

    // The tile's points into the grid and the callback, alone.
    void publish(std::uint32_t id, const std::vector<PendingPoint>& points) {
        std::vector<std::pair<CellKey, GridPoint>> placed;
        place(id, points, placed);
        add_placed(std::span(&id, 1), placed);
    }

    // The tile's points on the grid, appended to `placed` (those that cannot be placed are its errors).
    void place(std::uint32_t id, const std::vector<PendingPoint>& points,
               std::vector<std::pair<CellKey, GridPoint>>& placed) {
        const bool sixteen_bit = colour_is_16bit(points, [](const PendingPoint& p) {
            return std::max({p.point.rgb[0], p.point.rgb[1], p.point.rgb[2]});
        });
        const auto& tile = ds_.tiles[id];
        const RecordPlacer placer(tile, sixteen_bit);
        placed.reserve(placed.size() + points.size());
        for (const auto& pending : points) {
            MetricPoint p;
            try {
                p = placer.place(pending.point);
            } catch (const Error& e) {
                fail(tile.tile.path(), pending.offset, e.cause());
                continue;
            }
            try {
                const CellKey cell = grid_.cell_of(p.x, p.y);
                const GridPoint g = grid_.point_in(cell, p.x, p.y, p.z, p.rgb, p.intensity, p.classification, id);
                placed.emplace_back(cell, g);
            } catch (const Error& e) {
                fail(ds_.tiles[id].tile.path(), 0, "chunk point cannot be placed on the patch grid: " + e.cause());
            }
        }
    }

    // The points `placed` of the tiles `ids` into the grid, a cell at a time (one lookup each; in their order
    // within a cell), then the callback.
    void add_placed(std::span<const std::uint32_t> ids, std::vector<std::pair<CellKey, GridPoint>>& placed) {
        radix_sort(placed, [](const auto& p) { return cell_order(p.first); }, 64);  // (stable)
        grid_.add_in_cells(placed);
        loader_.loaded_ += placed.size();
        std::vector<CellKey> cells;
        for (const auto& [cell, point] : placed) {
            if (cells.empty() || cells.back() != cell) cells.push_back(cell);
        }
        loader_.tiles_done_ += ids.size();
        if (on_tile_done_) on_tile_done_(ids, cells);
    }

    ChunkPointLoader& loader_;
    const Dataset& ds_;
    PatchGrid& grid_;
    const bool direct_;
    const std::size_t max_errors_;
    ChunkPointLoader::TileDoneFn on_tile_done_;

    mutable std::mutex mutex_;
    std::unordered_map<std::uint32_t, TileState> tiles_;  // the tiles being read
    std::vector<std::uint32_t> active_;    // started tiles with reads left to hand out, oldest first
    TileIndex index_;                      // the tiles not started yet are its pending ones
    TileIndex unread_;                     // a placed dataset's tiles whose headers are not asked for yet
    std::vector<std::uint32_t> upcoming_;  // pending tiles of index_ nearest to upcoming_focus_, the next at the back
    std::pair<double, double> upcoming_focus_{0, 0};
    bool headers_done_ = false;            // every header asked for is read
    std::condition_variable headers_cv_;   // under mutex_: headers read, all read, or a cancel
    std::vector<std::uint32_t> unplaced_;  // tiles without bounds, not started yet; back = next
    std::vector<std::uint32_t> held_;      // tiles whose chunk points an overview sidecar holds
    bool cancelled_ = false;
    mutable std::mutex focus_mutex_;  // guards focus_ alone
    std::pair<double, double> focus_{0, 0};
    std::vector<ErrorRecord> errors_;
};

ChunkPointLoader::ChunkPointLoader(const Dataset& dataset, PatchGrid& grid, ChunkPointLoaderOptions options)
    : options_(options) {
    for (const auto& t : dataset.tiles) total_ += t.chunk_points;
    options_.reads.direct = options_.reads.direct || options_.direct_io;
    source_ = std::make_unique<Source>(*this, dataset, grid, options_.direct_io, options_.max_errors);
}

ChunkPointLoader::~ChunkPointLoader() {
    cancel();
    if (thread_.joinable()) thread_.join();
}

void ChunkPointLoader::set_focus(double x_m, double y_m) { source_->set_focus(x_m, y_m); }

void ChunkPointLoader::on_tile_done(TileDoneFn callback) {
    source_->set_on_tile_done(std::move(callback));
}

void ChunkPointLoader::start() {
    if (thread_.joinable()) return;
    thread_ = std::thread([this] { run(); });
}

void ChunkPointLoader::run() {
    std::thread headers;
    try {
        source_->publish_held(options_.release_overview && !options_.on_tile_records);
        if (source_->reads_headers()) {
            headers = std::thread([this] {
                try {
                    source_->read_headers(options_.header_threads);
                } catch (...) {
                    std::lock_guard lock(mutex_);
                    if (!failure_) failure_ = std::current_exception();
                }
            });
        }
        auto used = io::run_batch_reads(*source_, options_.reads);
        while (headers.joinable() && source_->more_tiles()) used = io::run_batch_reads(*source_, options_.reads);
        backend_used_ = used;
    } catch (...) {
        std::lock_guard lock(mutex_);
        failure_ = std::current_exception();
    }
    if (headers.joinable()) {
        source_->cancel();  // (a failure of the reads: the headers stop too)
        headers.join();
    }
    {
        std::lock_guard lock(mutex_);
        finished_ = true;
    }
    done_cv_.notify_all();
}

void ChunkPointLoader::cancel() { source_->cancel(); }

void ChunkPointLoader::wait() {
    if (!thread_.joinable()) return;
    std::unique_lock lock(mutex_);
    done_cv_.wait(lock, [&] { return finished_.load(); });
    if (failure_) std::rethrow_exception(failure_);
}

bool ChunkPointLoader::wait_for(std::chrono::milliseconds timeout) {
    if (!thread_.joinable()) return true;
    std::unique_lock lock(mutex_);
    return done_cv_.wait_for(lock, timeout, [&] { return finished_.load(); });
}

std::vector<ErrorRecord> ChunkPointLoader::errors() const { return source_->errors(); }

}  // namespace lidarscout::dataset
