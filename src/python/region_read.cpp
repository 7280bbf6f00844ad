// region_query, read_region and RegionStream over pipelines::read_region_points.
#include "python/region_read.hpp"

#include <algorithm>
#include <cmath>
#include <utility>

#include "core/error.hpp"
#include "core/polygon.hpp"
#include "core/thread_pool.hpp"

namespace lidarscout::python {
namespace {

unsigned pool_size(unsigned threads) { return threads ? threads : std::max(1u, std::thread::hardware_concurrency()); }

// Every point a read of `tiles` may keep: their points.
std::size_t most_points(const dataset::Dataset& ds, std::span<const std::uint32_t> tiles) {
    std::size_t n = 0;
    for (const auto t : tiles) n += ds.tiles[t].tile.header.point_count;
    return n;
}

std::vector<std::uint32_t> touched_tiles(const dataset::Dataset& ds, const RegionQuery& q, const std::string& stage) {
    auto tiles = pipelines::tiles_touching(ds, q.region);
    pipelines::require_touched_tiles(ds, tiles, q.region, stage, "the region");
    return tiles;
}

void append(const pipelines::RegionBatch& b, std::span<const pipelines::RegionPoint> points, PointTable& out) {
    for (const auto& p : points) out.push_back(point_record(p.point, p.x, p.y, p.z, b.tile));
}

}  // namespace

RegionQuery region_query(const std::optional<std::array<double, 4>>& bounds, const std::string& polygon,
                         const std::string& classes, const std::string& returns,
                         const std::string& intensity, const std::string& stage) {
    if (bounds && !polygon.empty()) throw Error(stage + ": give bounds or polygon, not both");
    RegionQuery q;
    q.filter = PointFilter::parse(classes, returns, intensity);
    if (bounds) {
        q.region = pipelines::bounds_region(*bounds, stage, "bounds");
    } else if (!polygon.empty()) {
        q.region = pipelines::polygon_region(read_polygon_argument(polygon));
    } else {  // every tile, every point (the dataset's bounds divided back to its units could miss an edge's)
        q.region = pipelines::box_region(-INFINITY, -INFINITY, INFINITY, INFINITY);
    }
    return q;
}

RegionRead read_region(const dataset::Dataset& ds, const RegionQuery& query, unsigned threads) {
    const auto tiles = touched_tiles(ds, query, "read");
    RegionRead r{PointTable(most_points(ds, tiles)), {}};
    ThreadPool pool(pool_size(threads));
    r.stats = pipelines::read_region_points(ds, tiles, query.region, query.filter, pool,
                                            [&](const pipelines::RegionBatch& b) { append(b, b.points, r.points); });
    return r;
}

RegionStream::RegionStream(std::shared_ptr<const dataset::Dataset> ds, RegionQuery query, unsigned threads,
                           std::size_t batch)
    : ds_(std::move(ds)), query_(std::move(query)), threads_(pool_size(threads)),
      batch_(std::max<std::size_t>(batch, 1)) {
    tiles_ = touched_tiles(*ds_, query_, "iter_read");
    thread_ = std::thread([this] { run(); });
}

RegionStream::~RegionStream() {
    cancel_ = true;
    changed_.notify_all();
    if (thread_.joinable()) thread_.join();
}

void RegionStream::run() {
    try {
        ThreadPool pool(threads_);
        pipelines::ReadWatch watch;
        watch.cancel = &cancel_;
        stats_ = pipelines::read_region_points(*ds_, tiles_, query_.region, query_.filter, pool,
                                               [this](const pipelines::RegionBatch& b) { take(b); }, watch,
                                               std::min(batch_, kStreamReadPoints));
        if (filling_.size() > 0) hand_over();
    } catch (...) {
        const std::lock_guard lock(mutex_);
        failure_ = std::current_exception();
    }
    const std::lock_guard lock(mutex_);
    finished_ = true;
    changed_.notify_all();
}

// The batch's points into tables of batch_ points, each full one handed over.
void RegionStream::take(const pipelines::RegionBatch& b) {
    std::span<const pipelines::RegionPoint> rest = b.points;
    while (!rest.empty() && !cancel_) {
        if (filling_.capacity() == 0) filling_ = PointTable(batch_);
        const std::size_t n = std::min(rest.size(), filling_.room());
        append(b, rest.first(n), filling_);
        rest = rest.subspan(n);
        if (filling_.room() == 0) hand_over();
    }
}

// Offers the table and waits until it has been taken (or the stream is stopped): the stream holds at most
// one full table beside the one Python works on.
void RegionStream::hand_over() {
    std::unique_lock lock(mutex_);
    if (!cancel_) ready_ = std::move(filling_);
    filling_ = PointTable(0);
    changed_.notify_all();
    changed_.wait(lock, [this] { return !ready_ || cancel_; });
}

std::optional<PointTable> RegionStream::next() {
    std::unique_lock lock(mutex_);
    changed_.wait(lock, [this] { return ready_ || finished_; });
    if (ready_) {
        std::optional<PointTable> out = std::move(ready_);
        ready_.reset();
        changed_.notify_all();
        return out;
    }
    if (failure_) std::rethrow_exception(std::exchange(failure_, nullptr));
    return std::nullopt;
}

}  // namespace lidarscout::python
