// Residency: the worth of tiles on screen, the choice of the next tile to decode and of what
// drops for it, decoding into LOD blocks and patch detail, the worker loop.
#include "viewer/residency.hpp"


#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>

#include "core/process_memory.hpp"
#include "core/throttle.hpp"
#include "core/thread_pool.hpp"
#include "core/thread_priority.hpp"
#include "viewer/point_sets.hpp"
#include "viewer/visibility.hpp"

namespace lidarscout::viewer {
namespace {

constexpr auto kPoll = std::chrono::milliseconds(100);
constexpr std::uint64_t kPiecePoints = ResidencyPolicy::kPiecePoints;

std::uint64_t coarse_bytes(const LodBlocks& blocks, double spacing_m) {
    std::uint64_t n = 0;
    for (const auto& b : blocks)
        n += b->level_end[coarse_level(*b, spacing_m)] * sizeof(render::PointAttr) + sizeof(LodBlock);
    return n;
}

}  // namespace

// Thrown between two pieces of a tile when the residency stops.
struct Stopped {};

Residency::Residency(const dataset::Dataset& dataset, const lidarscout::PatchGrid& grid, ResidencyOptions options)
    : dataset_(dataset), grid_(grid), options_(std::move(options)),
      ledger_(options_.ledger ? options_.ledger : std::make_shared<MemoryLedger>(options_.memory_budget)),
      policy_(dataset, grid, options_) {
    return_freed_memory();  // what a release frees must leave the process, or the budget bounds nothing
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
    if (thread_.joinable()) throw Error::in_stage("viewer", "the residency's worker was started twice");
    thread_ = std::thread([this] { run(); });
}

void Residency::set_camera(const render::Camera& camera) {
    {
        std::lock_guard lock(mutex_);
        camera_ = camera;
        has_camera_ = true;
        ++camera_version_;
        refresh_idle();
    }
    wake_.notify_all();
}

void Residency::set_budget(std::uint64_t bytes) {
    {
        std::lock_guard lock(mutex_);
        ledger_->set_budget(bytes);
        ++camera_version_;  // look again
        refresh_idle();
    }
    wake_.notify_all();
}

void Residency::set_min_screen_fraction(double fraction) {
    {
        std::lock_guard lock(mutex_);
        policy_.set_min_screen_fraction(fraction);
        ++camera_version_;  // look again
        refresh_idle();
    }
    wake_.notify_all();
}

std::uint64_t Residency::held() const {
    std::uint64_t bytes = details_bytes_;
    for (const auto& [tile, e] : policy_.entries()) bytes += e.bytes;
    for (const auto& [block, size] : retired_) bytes += block.expired() ? 0 : size;
    return bytes;
}

std::uint64_t Residency::publish_held() const {
    const std::uint64_t bytes = held() + decoding_bytes_;
    ledger_->set_residency_bytes(bytes);
    return bytes;
}

void Residency::retire(const LodBlocks& blocks) {
    for (const auto& b : blocks) retired_.emplace_back(b, b->bytes());
    blocks_cache_.clear();  // the residency itself no longer holds them
    blocks_version_ = 0;
}

bool Residency::drop(std::uint32_t tile) {
    auto& entries = policy_.entries();
    const auto it = entries.find(tile);
    if (it == entries.end()) return false;
    retire(it->second.blocks);
    entries.erase(it);
    return true;
}

bool Residency::prune_retired() {
    return std::erase_if(retired_, [](const auto& r) { return r.first.expired(); }) > 0;
}

std::vector<std::uint32_t> Residency::release(const std::vector<std::uint32_t>& tiles) {
    std::vector<std::uint32_t> dropped;  // tiles that went from full to coarse
    auto& entries = policy_.entries();
    for (const auto t : tiles) {
        const auto it = entries.find(t);
        if (it == entries.end()) continue;
        Entry& e = it->second;
        ++version_;
        retire(e.blocks);
        if (e.level == Level::Coarse) {
            entries.erase(it);
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

std::optional<Residency::Job> Residency::next_load(std::unique_lock<RankedMutex>& lock) {
    std::uint64_t seen = ~0ull;
    while (true) {
        wake_.wait_for(lock, kPoll, [&] { return stopping_ || camera_version_ != seen; });
        if (stopping_) return std::nullopt;
        seen = camera_version_;
        if (!has_camera_) continue;
        // A camera that moves every frame over a country of tiles: a look at most every kPoll,
        // its screen coverage of every tile computed without the lock that set_camera takes.
        if (!look_throttle_.due(last_in_view_)) {
            wake_.wait_for(lock, kPoll, [&] { return stopping_; });
            if (stopping_) return std::nullopt;
            seen = camera_version_;
        }
        look_throttle_.done();
        const render::Camera camera = camera_;
        const bool freed = prune_retired();
        lock.unlock();
        if (freed) trim_heap();  // released points go back to the system
        const std::uint64_t other = ledger_->outside_residency();
        const std::uint64_t visits_before = policy_.index_visits();  // the index: this thread's alone
        const auto fractions = policy_.screen_fractions(camera);
        const std::uint64_t visits = policy_.index_visits() - visits_before;
        lock.lock();
        index_visits_ += visits, last_look_visits_ = visits;
        last_in_view_ = fractions.size();
        if (stopping_) return std::nullopt;
        last_other_ = other;
        policy_.set_camera(camera, seen);
        auto dropped = release(policy_.stale_partials(fractions));
        const std::uint64_t budget = ledger_->budget();
        const auto choice = policy_.choose(fractions, other + held(), budget);
        const auto over = choice ? choice->victims : policy_.over_budget(other + held(), budget);
        const auto made_room = release(over);
        dropped.insert(dropped.end(), made_room.begin(), made_room.end());
        if (!dropped.empty()) {
            lock.unlock();
            notify(dropped, std::nullopt, {});
            lock.lock();
        }
        publish_held();
        if (!choice) {
            checked_version_ = seen;
            refresh_idle();
            continue;
        }
        // What was released is gone once no snapshot holds it (a frame being drawn): the load waits till then.
        const std::uint64_t incoming = choice->cap + choice->extra + choice->plan.transient;
        if (other + held() + incoming > ledger_->budget()) continue;
        busy_ = true;
        refresh_idle();
        ++loads_;
        loading_version_ = seen;
        // The points still to come, their bookkeeping, and what the decoding threads hold besides.
        decoding_bytes_ = incoming;
        peak_ = std::max(peak_, other + publish_held());
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
    // (named copies, not a structured binding: the lambda below captures them, which clang 14 refuses)
    const std::uint32_t tile = job.tile;
    const std::uint64_t cap = job.cap, piece_points = job.piece_points;
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

std::vector<lidarscout::CellKey> Residency::commit(std::uint32_t tile, Decoded decoded, bool& first) {
    std::lock_guard lock(mutex_);
    if (std::exchange(first, false)) drop(tile);  // its coarse levels, held since an earlier release
    std::vector<lidarscout::CellKey> cells;
    const std::uint64_t details_before = details_bytes_;
    for (auto& [cell, d] : decoded.detail) {
        cells.push_back(cell);
        // Found under mutex_ alone (every writer holds it); changed under details_mutex_ too.
        const auto it = details_.find(cell);
        if (it == details_.end()) {
            details_bytes_ += d.bytes();
            auto added = std::make_shared<const PatchDetail>(std::move(d));
            std::lock_guard details_lock(details_mutex_);
            details_.emplace(cell, std::move(added));
            continue;
        }
        auto merged = std::make_shared<PatchDetail>(*it->second);
        merge_detail(*merged, d);
        details_bytes_ += merged->bytes() - it->second->bytes();  // a layer the cell had none of (merges grow)
        std::lock_guard details_lock(details_mutex_);
        it->second = std::move(merged);
    }
    Entry& e = policy_.entries()[tile];
    e.level = Level::Full;
    e.coarse_bytes += coarse_bytes(decoded.blocks, options_.coarse_spacing_m);
    const std::uint64_t added = lod_bytes(decoded.blocks);
    e.bytes += added;
    e.blocks.insert(e.blocks.end(), decoded.blocks.begin(), decoded.blocks.end());
    e.last_seen = policy_.tick();
    decoding_bytes_ -= std::min(decoding_bytes_, added + details_bytes_ - details_before);
    ++version_;
    peak_ = std::max(peak_, last_other_ + publish_held());
    return cells;
}

void Residency::notify(const std::vector<std::uint32_t>& dropped, std::optional<std::uint32_t> loaded,
                       const std::vector<lidarscout::CellKey>& cells) const {
    if (options_.on_tile) {
        for (const auto t : dropped) options_.on_tile(t, false);
    }
    if (!cells.empty() && options_.on_detail) options_.on_detail(cells);
    if (loaded && options_.on_tile) options_.on_tile(*loaded, true);
}

void Residency::run() {
    // Decoding yields to drawing: this thread and the pool's (which inherit it) run at a lower
    // priority, so that frames keep their time while tiles stream in.
    lower_thread_priority(options_.decode_nice);
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
        refresh_idle();
        publish_held();
        if (error) {  // the pieces it had are dropped: a damaged file is not drawn in part
            policy_.failed().insert(tile);
            errors_.push_back(std::move(*error));
            if (drop(tile)) ++version_;
            continue;
        }
        if (capped && policy_.entries().contains(tile)) {
            Entry& e = policy_.entries().at(tile);
            e.partial = true;
            e.loaded_at = loading_version_;
            e.coverage = policy_.coverage(e, screen_fraction(policy_.camera(), dataset_.bounds(tile)));
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
        for (const auto& [tile, e] : policy_.entries())
            blocks_cache_.insert(blocks_cache_.end(), e.blocks.begin(), e.blocks.end());
        blocks_version_ = version_;
    }
    return blocks_cache_;
}

std::vector<lidarscout::CellKey> Residency::detail_cells() const {
    std::lock_guard lock(details_mutex_);
    std::vector<lidarscout::CellKey> out;
    out.reserve(details_.size());
    for (const auto& entry : details_) out.push_back(entry.first);
    return out;
}

std::shared_ptr<const PatchDetail> Residency::detail(lidarscout::CellKey cell) const {
    std::lock_guard lock(details_mutex_);
    const auto it = details_.find(cell);
    return it == details_.end() ? nullptr : it->second;
}

std::uint64_t Residency::version() const { return version_.load(); }

ResidencyStats Residency::stats() const {
    std::lock_guard lock(mutex_);
    ResidencyStats st;
    for (const auto& [tile, e] : policy_.entries()) {
        const bool full = e.level == Level::Full;
        (full ? st.full_tiles : st.coarse_tiles) += 1;
        const std::uint64_t points = lod_points(e.blocks);
        st.lod_points += points;
        if (full) st.full_points += points, st.bytes_full += e.bytes;
    }
    st.released = released_;
    st.loads = loads_;
    st.wanted = policy_.wanted(), st.wanted_full = policy_.wanted_full();
    st.largest_full = policy_.largest_full();
    st.bytes = held();
    st.decoding_bytes = decoding_bytes_;
    st.peak_bytes = peak_;
    st.budget = ledger_->budget();
    st.errors = errors_;
    st.in_view = last_in_view_;
    st.index_visits = index_visits_, st.look_visits = last_look_visits_;
    return st;
}

void Residency::refresh_idle() { idle_ = !busy_ && (!has_camera_ || checked_version_ == camera_version_); }

bool Residency::idle() const {
    return idle_.load();
}

}  // namespace lidarscout::viewer
