// Residency: the worth of tiles on screen, the choice of the next tile to decode and of what
// drops for it, decoding into LOD blocks and patch detail, the worker loop.
#include "viewer/residency.hpp"

#include <sys/resource.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cmath>
#include <limits>

#include "core/process_memory.hpp"
#include "core/throttle.hpp"
#include "core/thread_pool.hpp"
#include "viewer/point_sets.hpp"
#include "viewer/visibility.hpp"

namespace lidarscout::viewer {
namespace {

constexpr auto kPoll = std::chrono::milliseconds(100);
constexpr std::uint64_t kPiecePoints = 1u << 18;  // points decoded (whole chunks) before they are shown
constexpr std::uint64_t kMinPartialBytes = 4 * kPiecePoints * sizeof(render::PointAttr);  // worth a partial load
constexpr std::size_t kMaxTries = 64;  // candidates tried per look, best first

// Pixels by which showing `box` at spacing `shown_m` misses its own spacing `own_m`, at its
// nearest distance.
double error_px(const render::Camera& camera, const dataset::Bounds& box, double shown_m, double own_m) {
    return std::max(shown_m - own_m, 0.0) / pixel_footprint(camera, distance_to(camera, box));
}

std::uint64_t coarse_bytes(const LodBlocks& blocks, double spacing_m) {
    std::uint64_t n = 0;
    for (const auto& b : blocks)
        n += b->level_end[coarse_level(*b, spacing_m)] * sizeof(render::PointAttr) + sizeof(LodBlock);
    return n;
}

}  // namespace

// Thrown between two pieces of a tile when the residency stops.
struct Stopped {};

struct Residency::Choice {
    std::uint32_t tile = 0;
    std::vector<std::uint32_t> victims;
    std::uint64_t cap = 0;    // bytes of points it may take: less than the whole tile for a partial load
    std::uint64_t extra = 0;  // its blocks' and patch details' bookkeeping
    DecodePlan plan;          // its pieces and what decoding them holds besides
};

struct Residency::Room {
    std::vector<std::uint32_t> victims;
    std::uint64_t total = 0;  // bytes held once they are released
};

Residency::Residency(const dataset::Dataset& dataset, const dataset::PatchGrid& grid, ResidencyOptions options)
    : dataset_(dataset), grid_(grid), options_(std::move(options)) {
    return_freed_memory();  // what a release frees must leave the process, or the budget bounds nothing
    spacing_.reserve(dataset.tiles.size());
    for (const auto& t : dataset.tiles) spacing_.push_back(mean_point_spacing(t));
}

Residency::~Residency() { stop(); }

void Residency::stop() {
    {
        std::lock_guard lock(mutex_);
        stopping_ = true;
    }
    wake_.notify_all();
    if (thread_.joinable()) thread_.join();
}

void Residency::start() {
    thread_ = std::thread([this] { run(); });
}

void Residency::set_camera(const render::Camera& camera) {
    {
        std::lock_guard lock(mutex_);
        camera_ = camera;
        has_camera_ = true;
        ++camera_version_;
    }
    wake_.notify_all();
}

void Residency::set_budget(std::uint64_t bytes) {
    {
        std::lock_guard lock(mutex_);
        options_.memory_budget = bytes;
        ++camera_version_;  // look again
    }
    wake_.notify_all();
}

double Residency::gain_per_byte(std::uint32_t tile, double fraction) const {
    const auto& t = dataset_.tiles[tile];
    const double shown = tiles_.contains(tile) ? options_.coarse_spacing_m : grid_.patch_size() / options_.patch_texels;
    const double bytes = static_cast<double>(std::max<std::uint64_t>(tile_point_set_bytes(t), 1));
    return error_px(camera_, t.bounds_m, shown, spacing_[tile]) * fraction / bytes;
}

double Residency::value_per_byte(std::uint32_t tile, const Entry& entry) const {
    const auto& b = dataset_.tiles[tile].bounds_m;
    const double fraction = screen_fraction(camera_, b);
    if (fraction <= 0)
        return -1.0 / (1.0 + static_cast<double>(entry.last_seen));  // out of view: least recently seen first
    if (entry.level == Level::Full) {
        const double freed = static_cast<double>(std::max<std::uint64_t>(entry.bytes - entry.coarse_bytes, 1));
        return error_px(camera_, b, options_.coarse_spacing_m, spacing_[tile]) * fraction / freed;
    }
    const double texel = grid_.patch_size() / options_.patch_texels;
    return error_px(camera_, b, texel, options_.coarse_spacing_m) * fraction /
           static_cast<double>(std::max<std::uint64_t>(entry.bytes, 1));
}

std::optional<DecodePlan> Residency::plan_for(std::uint32_t tile, std::uint64_t room) const {
    const auto& t = dataset_.tiles[tile];
    return fitting_decode_plan(t, t.tile.header.point_count, std::max(1u, options_.decode_threads), kPiecePoints,
                               room);
}

std::uint64_t Residency::bookkeeping_bytes(std::uint32_t tile) const {
    const auto& b = dataset_.tiles[tile].bounds_m;
    const auto across = [&](double side) {
        return static_cast<std::uint64_t>(std::ceil(std::max(b.max_x - b.min_x, 0.0) / side) + 1) *
               static_cast<std::uint64_t>(std::ceil(std::max(b.max_y - b.min_y, 0.0) / side) + 1);
    };
    const auto texels = static_cast<std::uint64_t>(options_.patch_texels) * options_.patch_texels;
    const std::uint64_t detail = texels * 12 + sizeof(PatchDetail);  // height, count and colour per texel
    return across(options_.block_m) * sizeof(LodBlock) + across(grid_.patch_size()) * detail;
}

std::uint64_t Residency::held() const {
    std::uint64_t bytes = details_bytes_;
    for (const auto& [tile, e] : tiles_) bytes += e.bytes;
    for (const auto& [block, size] : retired_) bytes += block.expired() ? 0 : size;
    return bytes;
}

void Residency::retire(const LodBlocks& blocks) {
    for (const auto& b : blocks) retired_.emplace_back(b, b->bytes());
    blocks_cache_.clear();  // the residency itself no longer holds them
    blocks_version_ = 0;
}

bool Residency::drop(std::uint32_t tile) {
    const auto it = tiles_.find(tile);
    if (it == tiles_.end()) return false;
    retire(it->second.blocks);
    tiles_.erase(it);
    return true;
}

bool Residency::prune_retired() {
    return std::erase_if(retired_, [](const auto& r) { return r.first.expired(); }) > 0;
}

std::vector<Residency::Step> Residency::release_steps() const {
    // A full tile drops to its coarse levels, then to nothing; cheapest worth per byte first.
    std::vector<Step> steps;
    for (const auto& [tile, e] : tiles_) {
        const double v = value_per_byte(tile, e);
        if (e.level == Level::Coarse) {
            steps.push_back({v, tile, e.bytes});
            continue;
        }
        steps.push_back({v, tile, e.bytes - e.coarse_bytes});
        const Entry coarse{Level::Coarse, {}, e.coarse_bytes, 0, e.last_seen};
        steps.push_back({std::max(v, value_per_byte(tile, coarse)), tile, e.coarse_bytes});
    }
    std::stable_sort(steps.begin(), steps.end(), [](const Step& a, const Step& b) { return a.value < b.value; });
    return steps;
}

std::optional<Residency::Room> Residency::victims(std::uint64_t incoming, double gain, std::uint64_t total,
                                                  const std::vector<Step>& steps) const {
    const std::uint64_t budget = options_.memory_budget;
    Room room{{}, total};
    for (const Step& s : steps) {
        if (room.total + incoming <= budget) break;
        if (s.value * options_.hysteresis >= gain) return std::nullopt;
        room.victims.push_back(s.tile);
        room.total -= std::min(room.total, s.freed);
    }
    if (room.total + incoming > budget) return std::nullopt;
    return room;
}

std::vector<double> Residency::screen_fractions(const render::Camera& camera) const {
    std::vector<double> out(dataset_.tiles.size());
    for (std::size_t i = 0; i < out.size(); ++i) out[i] = screen_fraction(camera, dataset_.tiles[i].bounds_m);
    return out;
}

std::optional<Residency::Choice> Residency::choose(std::uint64_t other, const std::vector<double>& fractions) {
    ++tick_;
    wanted_ = wanted_full_ = 0;
    std::vector<std::pair<double, std::uint32_t>> candidates;  // (gain per byte, tile)
    for (std::uint32_t i = 0; i < dataset_.tiles.size(); ++i) {
        const double fraction = fractions[i];
        if (fraction <= options_.min_screen_fraction || failed_.contains(i)) continue;
        ++wanted_;
        const auto it = tiles_.find(i);
        if (it != tiles_.end()) it->second.last_seen = tick_;
        if (it != tiles_.end() && it->second.level == Level::Full) {
            wanted_full_ += !it->second.partial;
            continue;
        }
        candidates.emplace_back(gain_per_byte(i, fraction), i);
    }
    // The best that fits: a tile larger than the budget allows must not stop the others.
    std::sort(candidates.begin(), candidates.end(), std::greater<>());
    if (candidates.size() > kMaxTries) candidates.resize(kMaxTries);
    const auto steps = release_steps();
    const std::uint64_t total = other + held();
    for (const auto& [gain, tile] : candidates) {
        const auto& t = dataset_.tiles[tile];
        const std::uint64_t bytes = tile_point_set_bytes(t), extra = bookkeeping_bytes(tile);
        const std::uint64_t least =
            decode_plan(t, t.tile.header.point_count, std::max(1u, options_.decode_threads), 1).transient;
        auto room = victims(bytes + extra + least, gain, total, steps);
        if (!room) continue;
        const auto plan = plan_for(tile, options_.memory_budget - room->total - bytes - extra);  // `least` fitted
        return Choice{tile, std::move(room->victims), bytes, extra, *plan};
    }
    // None fits whole: the best one in part (its pieces in view first), in the room there is.
    for (const auto& [gain, tile] : candidates) {
        auto choice = partial_choice(tile, gain, total, steps);
        if (choice) return choice;
    }
    return std::nullopt;
}

std::optional<Residency::Choice> Residency::partial_choice(std::uint32_t tile, double gain, std::uint64_t total,
                                                           const std::vector<Step>& steps) const {
    const std::uint64_t budget = options_.memory_budget;
    Choice c{tile, {}, 0, bookkeeping_bytes(tile), {}};
    for (const Step& s : steps) {
        if (s.value * options_.hysteresis >= gain) break;
        c.victims.push_back(s.tile);
        total -= std::min(total, s.freed);
    }
    if (total + c.extra >= budget) return std::nullopt;
    const std::uint64_t room = budget - total - c.extra;
    // Its decoding takes at most a quarter of the room, else the least it can; the points the rest.
    auto plan = plan_for(tile, room / 4);
    if (!plan) plan = plan_for(tile, room);
    if (!plan) return std::nullopt;
    c.plan = *plan;
    c.cap = room - plan->transient;
    // The first piece is always decoded whole; less room than a few pieces is not worth a load.
    const auto& t = dataset_.tiles[tile];
    const std::uint64_t piece = std::min(tile_point_set_bytes(t), (plan->piece_points - 1 + largest_unit_points(t)) *
                                                                      sizeof(render::PointAttr));
    if (c.cap < std::max(piece, std::min(kMinPartialBytes, budget / 16))) return std::nullopt;
    return c;
}

double Residency::coverage(const Entry& entry, double fraction) const {
    double covered = 0;
    for (const auto& b : entry.blocks) covered += screen_fraction(camera_, b->bounds);
    return fraction > 0 ? std::min(covered / fraction, 1.0) : 1.0;
}

std::vector<std::uint32_t> Residency::stale_partials(const std::vector<double>& fractions) const {
    std::vector<std::uint32_t> out;
    for (const auto& [tile, e] : tiles_) {
        if (!e.partial || e.level != Level::Full || e.loaded_at == camera_version_ || fractions[tile] <= 0) continue;
        if (coverage(e, fractions[tile]) < 0.5 * e.coverage) out.push_back(tile);
    }
    return out;
}

std::vector<std::uint32_t> Residency::release(const std::vector<std::uint32_t>& tiles) {
    std::vector<std::uint32_t> dropped;  // tiles that went from full to coarse
    for (const auto t : tiles) {
        const auto it = tiles_.find(t);
        if (it == tiles_.end()) continue;
        Entry& e = it->second;
        ++version_;
        retire(e.blocks);
        if (e.level == Level::Coarse) {
            tiles_.erase(it);
            continue;
        }
        for (auto& b : e.blocks) b = coarse_copy(*b, options_.coarse_spacing_m);
        e.level = Level::Coarse;
        e.bytes = lod_bytes(e.blocks);
        ++released_;
        dropped.push_back(t);
    }
    return dropped;
}

std::optional<Residency::Job> Residency::next_load(std::unique_lock<std::mutex>& lock) {
    std::uint64_t seen = ~0ull;
    while (true) {
        wake_.wait_for(lock, kPoll, [&] { return stopping_ || camera_version_ != seen; });
        if (stopping_) return std::nullopt;
        seen = camera_version_;
        if (!has_camera_) continue;
        // A camera that moves every frame over a country of tiles: a look at most every kPoll,
        // its screen coverage of every tile computed without the lock that set_camera takes.
        if (!look_throttle_.due(dataset_.tiles.size())) {
            wake_.wait_for(lock, kPoll, [&] { return stopping_; });
            if (stopping_) return std::nullopt;
            seen = camera_version_;
        }
        look_throttle_.done();
        const render::Camera camera = camera_;
        const bool freed = prune_retired();
        lock.unlock();
        if (freed) trim_heap();  // released points go back to the system
        const std::uint64_t other = options_.other_bytes ? options_.other_bytes() : 0;
        const std::vector<double> fractions = screen_fractions(camera);
        lock.lock();
        if (stopping_) return std::nullopt;
        last_other_ = other;
        auto dropped = release(stale_partials(fractions));
        const auto choice = choose(other, fractions);
        const auto over = choice ? choice->victims
                                 : victims(0, std::numeric_limits<double>::infinity(), other + held(), release_steps())
                                       .value_or(Room{})
                                       .victims;
        const auto made_room = release(over);
        dropped.insert(dropped.end(), made_room.begin(), made_room.end());
        if (!dropped.empty()) {
            lock.unlock();
            notify(dropped, std::nullopt, {});
            lock.lock();
        }
        if (!choice) {
            checked_version_ = seen;
            continue;
        }
        // What was released is gone once no snapshot holds it (a frame being drawn): the load waits till then.
        const std::uint64_t incoming = choice->cap + choice->extra + choice->plan.transient;
        if (other + held() + incoming > options_.memory_budget) continue;
        busy_ = true;
        ++loads_;
        loading_version_ = seen;
        // The points still to come, their bookkeeping, and what the decoding threads hold besides.
        decoding_bytes_ = incoming;
        peak_ = std::max(peak_, other + held() + decoding_bytes_);
        return Job{choice->tile, choice->cap, choice->plan.piece_points};
    }
}

PointOrder Residency::decode_order() const {
    // In view first, then nearer first.
    return [camera = camera_](double x, double y, double z) {
        const auto p = camera.project(x, y, z);
        const bool seen = p && p->x >= 0 && p->y >= 0 && p->x < camera.width && p->y < camera.height;
        return (seen ? 0.0 : 1e12) + std::hypot(x - camera.x, y - camera.y, z - camera.z);
    };
}

void Residency::load(const Job& job, const PointOrder& order, ThreadPool& pool) {
    const auto [tile, cap, piece_points] = job;
    bool fold = true;  // a tile reloaded after a release has its points in the details already
    if (std::lock_guard lock(mutex_); folded_.contains(tile)) fold = false;
    bool first = true;  // guarded by mutex_: the first piece committed replaces the coarse levels
    const bool whole = cap >= tile_point_set_bytes(dataset_.tiles[tile]);
    const std::uint64_t max_points = whole ? ~0ull : cap / sizeof(render::PointAttr);
    decode_tile_pieces(dataset_.tiles[tile], dataset_.las_stride, pool, order, piece_points, max_points,
                       [&](PointSet&& piece) {
                           if (std::lock_guard lock(mutex_); stopping_) throw Stopped{};
                           if (!options_.has_rgb) paint_uncoloured(std::span(&piece, 1));
                           Decoded d;
                           if (fold) d.detail = tile_detail(piece, grid_, options_.patch_texels);
                           d.blocks = build_lod_blocks(piece, tile, options_.block_m, pool);
                           piece = PointSet{};
                           notify({}, std::nullopt, commit(tile, std::move(d), first));
                       });
    if (std::lock_guard lock(mutex_); fold && whole) folded_.insert(tile);  // every piece came
}

std::vector<dataset::CellKey> Residency::commit(std::uint32_t tile, Decoded decoded, bool& first) {
    std::lock_guard lock(mutex_);
    if (std::exchange(first, false)) drop(tile);  // its coarse levels, held since an earlier release
    std::vector<dataset::CellKey> cells;
    const std::uint64_t details_before = details_bytes_;
    for (auto& [cell, d] : decoded.detail) {
        cells.push_back(cell);
        const auto it = details_.find(cell);
        if (it == details_.end()) {
            details_bytes_ += d.bytes();
            details_.emplace(cell, std::make_shared<const PatchDetail>(std::move(d)));
            continue;
        }
        auto merged = std::make_shared<PatchDetail>(*it->second);
        merge_detail(*merged, d);
        it->second = std::move(merged);
    }
    Entry& e = tiles_[tile];
    e.level = Level::Full;
    e.coarse_bytes += coarse_bytes(decoded.blocks, options_.coarse_spacing_m);
    const std::uint64_t added = lod_bytes(decoded.blocks);
    e.bytes += added;
    e.blocks.insert(e.blocks.end(), decoded.blocks.begin(), decoded.blocks.end());
    e.last_seen = tick_;
    decoding_bytes_ -= std::min(decoding_bytes_, added + details_bytes_ - details_before);
    ++version_;
    peak_ = std::max(peak_, last_other_ + held() + decoding_bytes_);
    return cells;
}

void Residency::notify(const std::vector<std::uint32_t>& dropped, std::optional<std::uint32_t> loaded,
                       const std::vector<dataset::CellKey>& cells) const {
    if (options_.on_tile) {
        for (const auto t : dropped) options_.on_tile(t, false);
    }
    if (!cells.empty() && options_.on_detail) options_.on_detail(cells);
    if (loaded && options_.on_tile) options_.on_tile(*loaded, true);
}

void Residency::run() {
    // Decoding yields to drawing: this thread and the pool's (which inherit it) run at a lower
    // priority, so that frames keep their time while tiles stream in.
    errno = 0;
    const int nice = ::getpriority(PRIO_PROCESS, 0);
    if (errno == 0) ::setpriority(PRIO_PROCESS, static_cast<id_t>(::gettid()), nice + options_.decode_nice);
    ThreadPool pool(std::max(1u, options_.decode_threads));
    std::unique_lock lock(mutex_);
    while (const auto job = next_load(lock)) {
        const auto [tile, cap, piece_points] = *job;
        const PointOrder order = decode_order();
        lock.unlock();
        std::optional<ErrorRecord> error;
        const bool capped = cap < tile_point_set_bytes(dataset_.tiles[tile]);
        try {
            load(*job, order, pool);
        } catch (const Stopped&) {
            return;
        } catch (const Error& e) {
            error = ErrorRecord::of(e);
        } catch (const std::exception& e) {  // e.g. out of memory: still this tile's failure
            error = ErrorRecord{dataset_.tiles[tile].tile.path(), std::nullopt, e.what()};
        }
        trim_heap();  // the pieces' scratch, freed by the decoding threads, leaves the process
        lock.lock();
        decoding_bytes_ = 0;
        busy_ = false;
        if (error) {  // the pieces it had are dropped: a damaged file is not drawn in part
            failed_.insert(tile);
            errors_.push_back(std::move(*error));
            if (drop(tile)) ++version_;
            continue;
        }
        if (capped && tiles_.contains(tile)) {
            Entry& e = tiles_.at(tile);
            e.partial = true;
            e.loaded_at = loading_version_;
            e.coverage = coverage(e, screen_fraction(camera_, dataset_.tiles[tile].bounds_m));
        }
        lock.unlock();
        notify({}, tile, {});
        lock.lock();
    }
}

LodBlocks Residency::blocks() const {
    std::lock_guard lock(mutex_);
    if (blocks_version_ != version_) {
        blocks_cache_.clear();
        for (const auto& [tile, e] : tiles_)
            blocks_cache_.insert(blocks_cache_.end(), e.blocks.begin(), e.blocks.end());
        blocks_version_ = version_;
    }
    return blocks_cache_;
}

std::shared_ptr<const PatchDetail> Residency::detail(dataset::CellKey cell) const {
    std::lock_guard lock(mutex_);
    const auto it = details_.find(cell);
    return it == details_.end() ? nullptr : it->second;
}

std::uint64_t Residency::version() const {
    std::lock_guard lock(mutex_);
    return version_;
}

ResidencyStats Residency::stats() const {
    std::lock_guard lock(mutex_);
    ResidencyStats st;
    for (const auto& [tile, e] : tiles_) {
        const bool full = e.level == Level::Full;
        (full ? st.full_tiles : st.coarse_tiles) += 1;
        const std::uint64_t points = lod_points(e.blocks);
        st.lod_points += points;
        if (full) st.full_points += points, st.bytes_full += e.bytes;
    }
    st.released = released_;
    st.loads = loads_;
    st.wanted = wanted_, st.wanted_full = wanted_full_;
    st.bytes = held();
    st.decoding_bytes = decoding_bytes_;
    st.peak_bytes = peak_;
    st.budget = options_.memory_budget;
    st.errors = errors_;
    return st;
}

bool Residency::idle() const {
    std::lock_guard lock(mutex_);
    return !busy_ && (!has_camera_ || checked_version_ == camera_version_);
}

}  // namespace lidarscout::viewer
