// Scheduler: patch dependencies on tiles, the priority queues of the heightmap workers, the
// full-resolution loop under the memory budget, and the shared snapshot.
#include "viewer/scheduler.hpp"

#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <optional>
#include <unordered_map>
#include <utility>

#include "core/error.hpp"
#include "core/process_memory.hpp"
#include "core/throttle.hpp"
#include "core/thread_pool.hpp"
#include "nn/heightmap_network.hpp"
#include "viewer/residency.hpp"
#include "viewer/scheduler_detail.hpp"

namespace lidarscout::viewer {
namespace {

using dataset::CellKey;
using dataset::CellKeyHash;

constexpr auto kLoaderPoll = std::chrono::milliseconds(100);
constexpr std::uint64_t kNoVersion = ~0ull;
constexpr double kOutOfView = 1e12;  // added to the priority key of a cell out of view
constexpr auto kOutOfViewWait = std::chrono::milliseconds(50);  // heightmaps out of view: the next look
// When a work queue was last sorted (the camera version), and how often a long one may be.
struct QueueOrder {
    std::uint64_t version = kNoVersion;
    Throttle throttle{std::chrono::milliseconds(200), 4096};
};

struct Patch {
    bool candidate = false;  // its cell overlaps a tile: it gets a heightmap job
    int deps = 0;            // tiles overlapping its window whose chunk points are not in yet
    bool ready = false, linear_tried = false, cnn_tried = false;
    std::shared_ptr<const PatchHeightmap> base;   // linear or network
    bool base_is_cnn = false;
    std::shared_ptr<const PatchHeightmap> shown;  // base with the full-resolution detail laid over
    std::shared_ptr<const PointSet> chunk;        // its chunk points
    bool drawable = false;                        // listed in State::drawable (has shown or chunk)
    std::uint64_t key_version = kNoVersion;       // camera version of `key`
    double key = 0;                               // priority: lower first
};

std::uint64_t heightmap_bytes(const PatchHeightmap& h) { return h.heights.capacity() * 4 + h.colours.capacity() * 4; }

// Cells [first, last] whose span [origin + i * size, origin + (i + 1) * size) meets [lo - pad, hi + pad].
std::pair<std::int32_t, std::int32_t> cell_range(double lo, double hi, double origin, double size, double pad) {
    return {static_cast<std::int32_t>(std::floor((lo - pad - origin) / size)),
            static_cast<std::int32_t>(std::floor((hi + pad - origin) / size))};
}

// A tile's cells are enumerated from its header bounds only when the bounds are about as large
// as its data could fill: a few points in a box of a billion metres a side (one of the format
// test files) would otherwise enumerate 10^13 cells. Other tiles ("sparse") get the cells their
// chunk points fall in, once they are in.
constexpr double kCellsPerTile = 1024, kCellsPerChunkPoint = 16;

bool bounds_fit_data(const dataset::DatasetTile& t, const dataset::PatchGrid& grid, double pad) {
    const auto& b = t.bounds_m;
    const double w = (b.max_x - b.min_x + 2 * pad) / grid.patch_size() + 2;
    const double h = (b.max_y - b.min_y + 2 * pad) / grid.patch_size() + 2;
    return w * h <= kCellsPerTile + kCellsPerChunkPoint * static_cast<double>(t.chunk_points);
}

template <typename Fn>
void for_cells(const dataset::Bounds& b, const dataset::PatchGrid& grid, double pad, Fn&& fn) {
    const auto [x0, x1] = cell_range(b.min_x, b.max_x, grid.origin_x(), grid.patch_size(), pad);
    const auto [y0, y1] = cell_range(b.min_y, b.max_y, grid.origin_y(), grid.patch_size(), pad);
    for (std::int32_t iy = y0; iy <= y1; ++iy) {
        for (std::int32_t ix = x0; ix <= x1; ++ix) fn(CellKey{ix, iy});
    }
}

}  // namespace

std::uint64_t default_memory_budget() {
    const long pages = ::sysconf(_SC_PHYS_PAGES), page = ::sysconf(_SC_PAGESIZE);
    return pages > 0 && page > 0 ? static_cast<std::uint64_t>(pages) * page / 4 : (1ull << 30);
}

struct Scheduler::State {
    mutable std::mutex mutex;
    std::condition_variable wake;
    bool stopping = false;

    render::Camera camera;
    bool has_camera = false;
    std::uint64_t camera_version = 0;

    std::unordered_map<CellKey, Patch, CellKeyHash> patches;
    std::vector<std::vector<CellKey>> window_cells;  // per tile: candidate cells whose window it overlaps
    std::vector<bool> sparse;                        // per tile: its cells come from its points (bounds_fit_data)
    std::vector<CellKey> ready, cnn_ready;           // queues, best at the back once sorted
    QueueOrder ready_sorted, cnn_sorted;
    std::size_t candidates = 0, tiles_done = 0, linear_tried = 0, linear_made = 0, cnn_tried = 0;
    std::size_t in_flight = 0;  // heightmap jobs running
    bool loader_finish_handled = false;

    std::unique_ptr<nn::HeightmapNetwork> network;
    bool network_pending = false;  // the cnn worker is still loading it

    std::vector<std::string> notes;
    std::vector<ErrorRecord> errors;  // the scheduler's own (the network); the loader and residency keep theirs
    std::uint64_t version = 1;  // a snapshot's version: this plus the residency's
    bool hidden_changes = false;  // patches out of view changed since the snapshot's version moved
    const dataset::PatchGrid* grid = nullptr;
    mutable std::shared_ptr<const SceneSnapshot> snapshot;

    HeightmapBuildOptions build;
    double z_min = 0, z_max = 0;
    std::uint64_t patch_bytes = 0;  // heightmaps and chunk points held by `patches` (bytes_of)
    std::vector<CellKey> drawable;  // patches with a heightmap or chunk points: what snapshots list

    void changed() { ++version; }

    // A patch's picture changed: the snapshot's version moves when the patch is in view; out of
    // view the change waits for the next camera move (a still view whose picture is done must
    // not be redrawn for every heightmap built behind it: its refined frame would never come).
    void changed_patch(CellKey cell, Patch& p) {
        if (key_of(p, cell, *grid) >= kOutOfView) hidden_changes = true;
        else changed();
    }

    // The camera moved: changes held back out of view are shown.
    void camera_moved() {
        ++camera_version;
        if (std::exchange(hidden_changes, false)) changed();
    }

    // Priority of a cell for the current camera: visible ones first, then by distance.
    double key_of(Patch& p, CellKey cell, const dataset::PatchGrid& grid) {
        if (p.key_version == camera_version) return p.key;
        const auto box = cell_box(grid, cell, z_min, z_max);
        const double d = has_camera ? distance_to(camera, box) : 0.0;
        p.key = (has_camera && !box_in_view(camera, box) ? kOutOfView : 0.0) + d;
        p.key_version = camera_version;
        return p.key;
    }

    // Sorts `queue` (best last) when the camera or its content changed since the last sort, a
    // long queue at most every 200 ms: a moving camera changes every frame, and sorting hundreds
    // of thousands of cells each time held the lock the frames wait for.
    void sort_queue(std::vector<CellKey>& queue, QueueOrder& order, const dataset::PatchGrid& grid) {
        if (order.version == camera_version || !order.throttle.due(queue.size())) return;
        std::vector<std::pair<double, CellKey>> keyed;
        keyed.reserve(queue.size());
        for (const auto cell : queue) keyed.emplace_back(key_of(patches[cell], cell, grid), cell);
        std::sort(keyed.begin(), keyed.end(), [](const auto& a, const auto& b) { return a > b; });
        for (std::size_t i = 0; i < keyed.size(); ++i) queue[i] = keyed[i].second;
        order.version = camera_version;
        order.throttle.done();
    }

    // A cell a sparse tile's chunk points fell in (see bounds_fit_data): its heightmap waits
    // for the loader to finish (no tile counted it as a dependency).
    void add_sparse_candidate(CellKey cell, Patch& p) {
        p.candidate = true;
        ++candidates;
        if (loader_finish_handled) push_ready(cell, p);
    }

    void push_ready(CellKey cell, Patch& p) {
        if (p.ready || !p.candidate) return;
        p.ready = true;
        ready.push_back(cell);
        ready_sorted.version = kNoVersion;
    }

    // The heightmap shown for a patch: its base with the full-resolution detail over it.
    void update_shown(CellKey cell, Patch& p, const PatchDetail* detail) {
        if (!p.base) return;
        modify(cell, p, [&] { p.shown = detail ? share(overlay_detail(*p.base, *detail)) : p.base; });
        changed_patch(cell, p);
    }

    // Runs `change` on a patch's heightmaps or chunk points, keeping patch_bytes and the
    // drawable list up to date.
    template <class Change>
    void modify(CellKey cell, Patch& p, Change&& change) {
        patch_bytes -= bytes_of(p);
        change();
        patch_bytes += bytes_of(p);
        if (!p.drawable && (p.shown || p.chunk)) {
            p.drawable = true;
            drawable.push_back(cell);
        }
    }

    static std::uint64_t bytes_of(const Patch& p) {
        std::uint64_t bytes = 0;
        if (p.base) bytes += heightmap_bytes(*p.base);
        if (p.shown && p.shown != p.base) bytes += heightmap_bytes(*p.shown);
        if (p.chunk) bytes += p.chunk->points.capacity() * sizeof(render::PointAttr);
        return bytes;
    }

    // Kept as patches change: summing 500,000 patches under the lock for every look of the
    // residency stalled the frames of a country-sized dataset.
    std::uint64_t held_bytes(const dataset::PatchGrid& grid) const { return grid.memory_bytes() + patch_bytes; }
};

Scheduler::Scheduler(const dataset::Dataset& dataset, SchedulerOptions options)
    : dataset_(dataset), options_(std::move(options)), has_rgb_(survey_has_rgb(dataset)),
      state_(std::make_unique<State>()) {
    const auto [ox, oy] = dataset::patch_grid_origin(dataset);
    grid_ = std::make_unique<dataset::PatchGrid>(ox, oy);
    State& s = *state_;
    s.grid = grid_.get();
    s.build.patch.min_points = options_.min_points;
    s.build.patch.has_rgb = has_rgb_;
    s.build.footprints = tile_footprints(dataset);
    s.build.batch = options_.cnn_batch;
    s.z_min = dataset.bounds_m.min_z, s.z_max = dataset.bounds_m.max_z;
    const double pad = s.build.patch.spec.pad_m();
    s.window_cells.resize(dataset.tiles.size());
    const auto dense = [&](const dataset::DatasetTile& t) {
        return t.chunk_points > 0 && !t.bounds_m.empty() && bounds_fit_data(t, *grid_, pad);
    };
    s.sparse.resize(dataset.tiles.size());
    for (std::uint32_t i = 0; i < dataset.tiles.size(); ++i) {
        const auto& t = dataset.tiles[i];
        s.sparse[i] = !dense(t);
        if (!s.sparse[i]) for_cells(t.bounds_m, *grid_, 0.0, [&](CellKey c) { s.patches[c].candidate = true; });
    }
    for (std::uint32_t i = 0; i < dataset.tiles.size(); ++i) {
        const auto& t = dataset.tiles[i];
        if (s.sparse[i]) continue;
        for_cells(t.bounds_m, *grid_, pad, [&](CellKey c) {
            const auto it = s.patches.find(c);
            if (it == s.patches.end() || !it->second.candidate) return;
            ++it->second.deps;
            s.window_cells[i].push_back(c);
        });
    }
    for (const auto& [c, p] : s.patches) s.candidates += p.candidate;
    s.network_pending = options_.cnn;

    residency_ = std::make_unique<Residency>(dataset_, *grid_, residency_options());
    loader_ = std::make_unique<dataset::ChunkPointLoader>(dataset_, *grid_, options_.loader);
    loader_->on_tile_done([this](std::uint32_t tile, std::span<const CellKey> cells) { on_tile_done(tile, cells); });
    if (options_.camera) set_camera(*options_.camera);
    loader_->start();
    for (unsigned i = 0; i < std::clamp(options_.heightmap_threads, 1u, max_threads()); ++i) {
        threads_.emplace_back([this] { heightmap_worker(); });
    }
    if (options_.cnn) threads_.emplace_back([this] { cnn_worker(); });
    threads_.emplace_back([this] { loader_watch(); });
    if (options_.full_res) residency_->start();
}

Scheduler::~Scheduler() {
    loader_->cancel();
    {
        std::lock_guard lock(state_->mutex);
        state_->stopping = true;
    }
    state_->wake.notify_all();
    residency_->stop();  // its hooks use the state and the residency itself
    for (auto& t : threads_) t.join();
    loader_.reset();  // joins the reader thread (its callback uses the state)
    residency_.reset();
    state_.reset();
    grid_.reset();
    trim_heap();  // what the session held goes back to the system, not to the allocator's free lists
}

std::pair<double, double> Scheduler::look_at_ground(const render::Camera& camera, const dataset::Bounds& bounds) {
    const auto f = camera.basis().forward;
    const double ground = bounds.empty() ? 0.0 : 0.5 * (bounds.min_z + bounds.max_z);
    const double height = std::max(camera.z - ground, 1.0);
    const double horizontal = std::hypot(f[0], f[1]);
    double t = f[2] < -1e-6 ? height / -f[2] : height;  // looking up or level: a camera height ahead
    if (!bounds.empty()) {
        const double extent = std::hypot(bounds.max_x - bounds.min_x, bounds.max_y - bounds.min_y) + height;
        t = std::min(t, 2.0 * extent);
    }
    if (horizontal < 1e-9) return {camera.x, camera.y};
    return {camera.x + f[0] * t, camera.y + f[1] * t};
}

void Scheduler::set_camera(const render::Camera& camera) {
    {
        std::lock_guard lock(state_->mutex);
        const render::Camera& c = state_->camera;
        if (state_->has_camera && c.x == camera.x && c.y == camera.y && c.z == camera.z &&
            c.yaw_deg == camera.yaw_deg && c.pitch_deg == camera.pitch_deg && c.fov_deg == camera.fov_deg &&
            c.width == camera.width && c.height == camera.height) {
            return;
        }
        state_->camera = camera;
        state_->has_camera = true;
        state_->camera_moved();
    }
    const auto [x, y] = look_at_ground(camera, dataset_.bounds_m);
    loader_->set_focus(x, y);
    state_->wake.notify_all();
    residency_->set_camera(camera);
}

void Scheduler::set_memory_budget(std::uint64_t bytes) {
    residency_->set_budget(bytes ? bytes : default_memory_budget());
}

ResidencyOptions Scheduler::residency_options() {
    ResidencyOptions r = options_.residency;
    r.memory_budget = options_.memory_budget ? options_.memory_budget : default_memory_budget();
    r.decode_threads =
        options_.decode_threads ? options_.decode_threads : std::max(1u, std::thread::hardware_concurrency());
    r.has_rgb = has_rgb_;
    r.patch_texels = state_->build.patch.spec.patch_texels;
    r.other_bytes = [this] {
        std::lock_guard lock(state_->mutex);
        return state_->held_bytes(*grid_);
    };
    r.on_detail = [this](const std::vector<CellKey>& cells) { show_detail(cells); };
    r.on_tile = [this](std::uint32_t tile, bool loaded) {
        if (!loaded) {  // the cached snapshot would keep the released points alive until the next frame
            std::lock_guard lock(state_->mutex);
            state_->snapshot.reset();
        }
        emit({loaded ? SchedulerEvent::Kind::FullResLoaded : SchedulerEvent::Kind::FullResReleased, tile, {}});
    };
    return r;
}

void Scheduler::emit(const SchedulerEvent& event) const {
    if (options_.on_event) options_.on_event(event);
}

void Scheduler::on_tile_done(std::uint32_t tile, std::span<const CellKey> cells) {
    State& s = *state_;
    std::vector<std::pair<CellKey, std::shared_ptr<const PointSet>>> sets;
    for (const auto cell : cells) {
        auto set = std::make_shared<PointSet>(cell_point_set(*grid_, cell));
        if (set->points.empty()) continue;
        if (!has_rgb_) paint_uncoloured(std::span(set.get(), 1));
        set->cache_key = render::new_cache_key();  // complete: shared read-only from here
        sets.emplace_back(cell, std::move(set));
    }
    {
        std::lock_guard lock(s.mutex);
        for (auto& entry : sets) {  // not a structured binding: clang 14 cannot capture one
            Patch& p = s.patches[entry.first];
            s.modify(entry.first, p, [&] { p.chunk = std::move(entry.second); });
            s.changed_patch(entry.first, p);
            if (s.sparse[tile] && !p.candidate) s.add_sparse_candidate(entry.first, p);
        }
        for (const auto cell : s.window_cells[tile]) {
            Patch& p = s.patches[cell];
            if (--p.deps == 0) s.push_ready(cell, p);
        }
        ++s.tiles_done;
    }
    s.wake.notify_all();
    emit({SchedulerEvent::Kind::TileDone, tile, {}});
}

void Scheduler::heightmap_worker() {
    State& s = *state_;
    std::unique_lock lock(s.mutex);
    while (true) {
        s.wake.wait(lock, [&] { return s.stopping || !s.ready.empty(); });
        if (s.stopping) return;
        s.sort_queue(s.ready, s.ready_sorted, *grid_);
        const CellKey cell = s.ready.back();
        // A patch out of view waits while the tiles in view decode: their points improve the
        // picture, its heightmap does not (a country's patches would hold the cores for minutes).
        if (s.key_of(s.patches[cell], cell, *grid_) >= kOutOfView && options_.full_res && !residency_->idle()) {
            s.wake.wait_for(lock, kOutOfViewWait);
            continue;
        }
        s.ready.pop_back();
        ++s.in_flight;
        lock.unlock();
        auto h = linear_heightmap(*grid_, cell, s.build.patch);
        if (h && !mask_to_footprints(*h, s.build.footprints)) h.reset();
        lock.lock();
        --s.in_flight;
        Patch& p = s.patches[cell];
        p.linear_tried = true;
        ++s.linear_tried;
        if (!h) continue;
        ++s.linear_made;
        if (!p.base_is_cnn) {
            s.modify(cell, p, [&] { p.base = share(std::move(*h)); });
            s.update_shown(cell, p, residency_->detail(cell).get());
        }
        if (s.network || s.network_pending) {
            s.cnn_ready.push_back(cell);
            s.cnn_sorted.version = kNoVersion;
            s.wake.notify_all();
        }
        lock.unlock();
        emit({SchedulerEvent::Kind::LinearHeightmap, 0, cell});
        lock.lock();
    }
}

void Scheduler::cnn_worker() {
    State& s = *state_;
    {
        // LibTorch's start-up (dlopen, ~0.5-1 s of CPU, holding the dynamic loader's lock that
        // new threads need) waits until there is work for it: the first linear heightmap. Loaded
        // at once, it delayed the first frame of chunk points from 0.13 s to 0.9 s.
        std::unique_lock lock(s.mutex);
        while (!s.stopping && s.cnn_ready.empty() && !loader_->finished()) {
            s.wake.wait_for(lock, std::chrono::milliseconds(50));
        }
        if (s.stopping) return;
    }
    std::unique_ptr<nn::HeightmapNetwork> network;
    std::string note;
    try {
        const std::string path = options_.model_path.empty() ? nn::default_model_path() : options_.model_path;
        network = std::make_unique<nn::HeightmapNetwork>(nn::HeightmapNetwork::load(path, 1));
    } catch (const std::exception& e) {
        note = std::string("no heightmap network, linear heightmaps only: ") + e.what();
    }
    std::unique_lock lock(s.mutex);
    s.network_pending = false;
    if (!network) {
        s.notes.push_back(note);
        s.cnn_ready.clear();
        return;
    }
    s.network = std::move(network);
    ThreadPool pool(1);
    while (true) {
        s.wake.wait(lock, [&] { return s.stopping || !s.cnn_ready.empty(); });
        if (s.stopping) return;
        s.sort_queue(s.cnn_ready, s.cnn_sorted, *grid_);
        std::vector<CellKey> batch;
        while (!s.cnn_ready.empty() && batch.size() < std::max<std::size_t>(1, options_.cnn_batch)) {
            batch.push_back(s.cnn_ready.back());
            s.cnn_ready.pop_back();
        }
        ++s.in_flight;
        lock.unlock();
        std::vector<PatchHeightmap> built;
        try {
            built = build_cnn_heightmaps(*grid_, batch, *s.network, s.build, pool);
        } catch (const std::exception& e) {
            lock.lock();
            s.errors.push_back(ErrorRecord::of(Error::in_stage("heightmap network", e.what())));
            lock.unlock();
        }
        lock.lock();
        --s.in_flight;
        s.cnn_tried += batch.size();
        for (const auto cell : batch) s.patches[cell].cnn_tried = true;
        for (auto& h : built) {
            const CellKey cell = h.cell;
            Patch& p = s.patches[cell];
            s.modify(cell, p, [&] { p.base = share(std::move(h)); });
            p.base_is_cnn = true;
            s.update_shown(cell, p, residency_->detail(cell).get());
        }
        lock.unlock();
        for (const auto& h : built) emit({SchedulerEvent::Kind::CnnHeightmap, 0, h.cell});
        lock.lock();
    }
}

void Scheduler::loader_watch() {
    State& s = *state_;
    while (!loader_->wait_for(kLoaderPoll)) {
        std::lock_guard lock(s.mutex);
        if (s.stopping) return;
    }
    {
        std::lock_guard lock(s.mutex);
        s.loader_finish_handled = true;  // tiles that never loaded: build what can be
        for (auto& [cell, p] : s.patches) s.push_ready(cell, p);
    }
    s.wake.notify_all();
}

void Scheduler::show_detail(const std::vector<CellKey>& cells) {
    State& s = *state_;
    std::lock_guard lock(s.mutex);
    for (const auto cell : cells) {
        const auto p = s.patches.find(cell);
        if (p != s.patches.end()) s.update_shown(cell, p->second, residency_->detail(cell).get());
    }
}

std::shared_ptr<const SceneSnapshot> Scheduler::snapshot() const {
    State& s = *state_;
    std::lock_guard lock(s.mutex);
    const std::uint64_t residency = residency_->version();
    if (s.snapshot && s.snapshot->version == s.version + residency) return s.snapshot;  // both only grow
    auto snap = std::make_shared<SceneSnapshot>();
    snap->version = s.version + residency;
    for (const auto cell : s.drawable) {  // not every patch: a country has 500,000
        const Patch& p = s.patches.at(cell);
        if (p.shown) snap->heightmaps.push_back(p.shown);
        else if (p.chunk) snap->chunk_points.push_back(p.chunk);
    }
    snap->full_points = residency_->blocks();
    s.snapshot = std::move(snap);
    return s.snapshot;
}

std::shared_ptr<const PatchHeightmap> Scheduler::heightmap(dataset::CellKey cell) const {
    std::lock_guard lock(state_->mutex);
    const auto it = state_->patches.find(cell);
    return it == state_->patches.end() ? nullptr : it->second.shown;
}

SchedulerStats Scheduler::stats() const {
    const State& s = *state_;
    SchedulerStats st;
    st.tiles = dataset_.tiles.size();
    st.chunk_points = {loader_->loaded() + loader_->failed(), loader_->total()};
    st.chunk_points_loaded = loader_->loaded();
    const auto loader_errors = loader_->errors();  // before our lock: the loader's own is taken
    std::lock_guard lock(s.mutex);
    std::size_t loadable = 0;
    for (const auto& t : dataset_.tiles) loadable += t.chunk_points > 0;
    st.tiles_loaded = {s.tiles_done, loadable};
    st.linear = {s.linear_tried, s.candidates};
    if (s.network) st.cnn = {s.cnn_tried, s.linear_made};
    for (const auto cell : s.drawable) {  // every patch with a heightmap is drawable
        const Patch& p = s.patches.at(cell);
        if (!p.base) continue;
        (p.base_is_cnn ? st.heightmaps_cnn : st.heightmaps_linear) += 1;
    }
    st.heightmap_jobs_pending = s.ready.size() + s.cnn_ready.size() + s.in_flight;
    const ResidencyStats r = residency_->stats();
    st.full_res = {r.wanted_full, r.wanted};
    st.full_res_tiles = r.full_tiles;
    st.coarse_tiles = r.coarse_tiles;
    st.full_res_points = r.full_points;
    st.lod_points = r.lod_points;
    st.full_res_released = r.released;
    st.full_res_loads = r.loads;
    st.bytes_full_res = r.bytes;
    st.bytes_decoding = r.decoding_bytes;
    st.bytes_used = s.held_bytes(*grid_) + r.bytes + r.decoding_bytes;
    st.peak_bytes_used = std::max(r.peak_bytes, st.bytes_used);
    st.memory_budget = r.budget;
    st.notes = s.notes;
    if (s.network) st.notes.push_back("heightmap network: " + s.network->path());
    st.errors = s.errors;
    st.errors.insert(st.errors.end(), loader_errors.begin(), loader_errors.end());
    st.errors.insert(st.errors.end(), r.errors.begin(), r.errors.end());
    return st;
}

bool Scheduler::idle() const {
    const State& s = *state_;
    if (!loader_->finished()) return false;
    std::lock_guard lock(s.mutex);
    return s.loader_finish_handled && s.ready.empty() && s.cnn_ready.empty() && s.in_flight == 0 &&
           !s.network_pending && (!options_.full_res || residency_->idle());
}

bool Scheduler::points_loading() const { return options_.full_res && !residency_->idle(); }

}  // namespace lidarscout::viewer
