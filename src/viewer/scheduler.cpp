// Scheduler: patch dependencies on tiles, the priority queues of the heightmap workers, the
// full-resolution loop under the memory budget, and the shared snapshot.
#include "viewer/scheduler.hpp"

#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <numeric>
#include <optional>
#include <unordered_map>
#include <unordered_set>
#include <utility>

#include "core/error.hpp"
#include "core/process_memory.hpp"
#include "core/ranked_mutex.hpp"
#include "core/thread_pool.hpp"
#include "core/thread_priority.hpp"
#include "nn/heightmap_network.hpp"
#include "viewer/cell_blocks.hpp"
#include "viewer/process_budget.hpp"
#include "viewer/residency.hpp"
#include "viewer/patch_detail.hpp"

namespace lidarscout::viewer {
namespace {

constexpr auto kLoaderPoll = std::chrono::milliseconds(100);
constexpr std::uint64_t kNoVersion = ~0ull;
constexpr double kOutOfView = 1e12;  // added to the priority key of a cell out of view
constexpr auto kOutOfViewWait = std::chrono::milliseconds(50);  // heightmaps out of view: the next look
// Heightmaps within the budget: a new one is built while all the data stays under kBuildShare of it;
// above kTrimShare, or for a nearer one, the farthest are let go until the data is under kKeepShare
// (they are built again when they come near), which leaves room for the next ones until the next look.
// The rest of the budget is the residency's room to load the tiles in view.
constexpr double kKeepShare = 0.7, kBuildShare = 0.8, kTrimShare = 0.9;
// Room for kRoomBatch new heightmaps between two looks, below SchedulerOptions::least_heightmaps.
constexpr std::size_t kRoomBatch = 64;
constexpr auto kRoomLook = std::chrono::milliseconds(250);  // how often the held heightmaps are weighed
// While the chunk points load, full resolution only for the tiles that fill this share of the view or more (the
// camera is close to them): the rest of the overview comes first. A country seen whole had its chunk points 0.3 s
// later while tiles of a 152,100th of the view each were decoded beside them.
constexpr double kLoadingScreenFraction = 0.02;
// A batch's chunk points are read into their blocks' sets (Scheduler::show_chunk_points) at once when it has this many
// cells, else with the batches that follow, kChunkReading after the last reading at most: a local country's tiles
// come one at a time, and each block had been read again for each of the ~60 tiles it meets (its frames 2.6 -> 7.1
// ms median in bench_view's flight over 152,100 tiles while they loaded).
constexpr std::size_t kChunkBatchCells = 1024;
constexpr auto kChunkReading = std::chrono::milliseconds(100);

struct Patch {
    bool candidate = false;  // its cell overlaps a tile: it gets a heightmap job
    bool counted = false;    // a candidate from the tiles' bounds: `deps` counts the tiles of its window
    int deps = 0;            // tiles overlapping its window whose chunk points are not in yet
    bool ready = false, linear_tried = false, cnn_tried = false, linear_made = false;
    std::shared_ptr<const PatchHeightmap> base;   // linear or network
    bool base_is_cnn = false;
    std::shared_ptr<const PatchHeightmap> shown;  // base with the full-resolution detail laid over
    bool chunk = false;     // it has chunk points (in its block's BlockChunks: CellBlocks::Block::chunks)
    bool drawable = false;  // listed in its block's drawable cells (has shown or chunk)
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

bool bounds_fit_data(const dataset::DatasetTile& t, const lidarscout::PatchGrid& grid, double pad) {
    const auto& b = t.bounds_m;
    const double w = (b.max_x - b.min_x + 2 * pad) / grid.patch_size() + 2;
    const double h = (b.max_y - b.min_y + 2 * pad) / grid.patch_size() + 2;
    return w * h <= kCellsPerTile + kCellsPerChunkPoint * static_cast<double>(t.chunk_points);
}

template <typename Fn>
void for_cells(const dataset::Bounds& b, const lidarscout::PatchGrid& grid, double pad, Fn&& fn) {
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
    // Rank 2 of the lock order in scheduler.hpp: between the residency's lock and its details' lock.
    mutable RankedMutex mutex{2, "scheduler state"};
    std::condition_variable_any wake;
    bool stopping = false;

    render::Camera camera;
    bool has_camera = false;
    std::uint64_t camera_version = 0;

    CellTable<Patch> patches;  // (core/cell_table.hpp: a reference to a patch stays good as patches are added)
    std::uint64_t table_bytes = 0;  // what `patches` holds itself, counted in the ledger (count_table)
    std::vector<bool> sparse;  // per tile: its cells come from its points (bounds_fit_data)
    CellBlocks blocks;         // the ready, network-ready and drawable cells, by block (cell_blocks.hpp)
    std::size_t candidates = 0, tiles_done = 0, linear_tried = 0, linear_made = 0, cnn_tried = 0;
    std::size_t loadable = 0;                     // tiles with chunk points
    std::size_t shown_linear = 0, shown_cnn = 0;  // patches whose base heightmap is of each kind
    std::unordered_set<CellKey, CellKeyHash> with_base;  // patches holding a heightmap (what may be let go)
    std::size_t least_heightmaps = 0;              // SchedulerOptions::least_heightmaps
    std::size_t let_go = 0;                        // heightmaps let go for room (built again when near)
    std::uint64_t no_room_version = kNoVersion;    // camera version at which the nearest job found no room
    std::chrono::steady_clock::time_point room_looked{};  // the last weighing of the held heightmaps
    std::uint64_t patch_visits = 0;               // patches examined by snapshots and job choices
    std::uint64_t snapshot_visits = 0, job_visits = 0;  // patches and blocks: the last snapshot, the last job

    std::uint64_t work() const { return patch_visits + blocks.visits(); }
    std::size_t in_flight = 0;  // heightmap jobs running
    bool loader_finish_handled = false;

    std::unique_ptr<nn::HeightmapNetwork> network;
    bool network_pending = false;  // the cnn worker is still loading it
    int network_room = -1;          // set_network_room's latest answer (-1: none yet)
    bool network_declined = false;  // no room: not loaded

    std::vector<std::string> notes;
    std::vector<ErrorRecord> errors;  // the scheduler's own (the network); the loader and residency keep theirs
    std::uint64_t version = 1;  // a snapshot's version: this plus the residency's
    bool hidden_changes = false;  // patches out of view changed since the snapshot's version moved
    const lidarscout::PatchGrid* grid = nullptr;
    mutable std::shared_ptr<const SceneSnapshot> snapshot;
    std::uint64_t snapshot_camera = 0;  // camera_version when it was made
    std::chrono::steady_clock::time_point snapshot_made{};
    std::chrono::duration<double> snapshot_cost{0};  // what making it took

    HeightmapBuildOptions build;
    double z_min = 0, z_max = 0;
    Surface surface = Surface::All;  // what the detail is laid over as (set_surface)
    std::vector<CellKey> restyle;    // patches with detail still showing another surface
    std::size_t restyling = 0;       // of those, being laid over now (outside the lock)
    // The budget, the grid's bytes and the heightmaps and chunk points held by `patches` (bytes_of),
    // kept as they change (summing 500,000 patches for every look of the residency stalled the
    // frames of a country-sized dataset); shared with the residency.
    std::shared_ptr<MemoryLedger> ledger;

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
    double key_of(Patch& p, CellKey cell, const lidarscout::PatchGrid& grid) {
        ++patch_visits;
        if (p.key_version == camera_version) return p.key;
        const auto box = cell_box(grid, cell, z_min, z_max);
        const double d = has_camera ? distance_to(camera, box) : 0.0;
        p.key = (has_camera && !box_in_view(camera, box) ? kOutOfView : 0.0) + d;
        p.key_version = camera_version;
        return p.key;
    }

    // The priority key a block box's cells cannot beat (a lower bound of key_of).
    double box_key(const dataset::Bounds& box) const {
        if (!has_camera) return 0.0;
        return (box_in_view(camera, box) ? 0.0 : kOutOfView) + distance_to(camera, box);
    }

    // Takes the cell of `list` to work on next: the one of least key (in view and nearest first).
    std::optional<CellKey> take_next(CellBlocks::List list, double* key = nullptr) {
        const std::uint64_t before = work();
        const auto cell = blocks.take_nearest(
            list, [&](const dataset::Bounds& box) { return box_key(box); },
            [&](CellKey c) { return key_of(patches.at(c), c, *grid); });
        if (cell && key) *key = key_of(patches.at(*cell), *cell, *grid);
        job_visits = work() - before;
        return cell;
    }

    // A cell a sparse tile's chunk points fell in (see bounds_fit_data): its heightmap waits
    // for the loader to finish (no tile counted it as a dependency).
    void add_sparse_candidate(CellKey cell, Patch& p) {
        p.candidate = true;
        ++candidates;
        if (loader_finish_handled) push_ready(cell, p);
    }

    // Calls fn(patch, cell, n) for the candidates counted from the tiles' bounds whose window (the cell +- the
    // recon padding) the dense tiles of `tiles` overlap, once for each cell, `n` the tiles whose windows hold it
    // (one lookup each: a country's tiles share their windows' cells). Computed again, in groups of tiles whose
    // cells stay a few megabytes: kept per tile, they held tens of MB for a country.
    template <class Fn>
    void for_window_cells_of(std::span<const std::uint32_t> tiles, std::span<const dataset::DatasetTile> all,
                             Fn&& fn) {
        constexpr std::size_t kGroup = 16384;
        std::vector<CellKey> cells;
        for (std::size_t first = 0; first < tiles.size(); first += kGroup) {
            cells.clear();
            for (const std::uint32_t t : tiles.subspan(first, std::min(kGroup, tiles.size() - first))) {
                if (!sparse[t]) for_cells(all[t].bounds_m, *grid, build.patch.spec.pad_m(), [&](CellKey c) {
                    cells.push_back(c);
                });
            }
            sort_cells(cells);
            for (std::size_t i = 0, j = 0; i < cells.size(); i = j) {
                for (j = i + 1; j < cells.size() && cells[j] == cells[i];) ++j;
                Patch* p = patches.find(cells[i]);
                if (p && p->counted) fn(*p, cells[i], static_cast<int>(j - i));
            }
        }
    }

    void push_ready(CellKey cell, Patch& p) {
        if (p.ready || !p.candidate) return;
        p.ready = true;
        blocks.add(CellBlocks::Ready, cell);
    }

    // The heightmap shown for a patch: its base with the full-resolution detail over it.
    void update_shown(CellKey cell, Patch& p, const PatchDetail* detail) {
        if (!p.base) return;
        set_shown(cell, p, detail ? share(overlay_detail(*p.base, *detail, surface)) : p.base);
    }

    void set_shown(CellKey cell, Patch& p, std::shared_ptr<const PatchHeightmap> shown) {
        modify(cell, p, [&] { p.shown = std::move(shown); });
        changed_patch(cell, p);
    }

    // Runs `change` on a patch's heightmaps or chunk points, keeping the ledger, the counts of
    // heightmap kinds and the drawable lists up to date.
    template <class Change>
    void modify(CellKey cell, Patch& p, Change&& change) {
        const std::uint64_t before = bytes_of(p);
        count_kind(p, -1);
        change();
        count_kind(p, 1);
        if (p.base) with_base.insert(cell);
        else with_base.erase(cell);
        ledger->add_patch_bytes(static_cast<std::int64_t>(bytes_of(p)) - static_cast<std::int64_t>(before));
        CellBlocks::Block& b = blocks.block_of(cell);
        b.changed = true;
        if (!p.drawable && (p.shown || p.chunk)) {
            p.drawable = true;
            blocks.add(CellBlocks::Drawable, cell);
        }
    }

    // The patch table's own bytes (a country has 600,000 patches: about 70 MB) in the ledger, so
    // that the budget bounds them too. Called after patches are added.
    void count_table() {
        const std::uint64_t bytes = patches.memory_bytes();
        ledger->add_patch_bytes(static_cast<std::int64_t>(bytes) - static_cast<std::int64_t>(table_bytes));
        table_bytes = bytes;
    }

    // A heightmap of about a patch's size fits below kBuildShare of the budget (or fewer than the least held).
    bool room_for_heightmap() const {
        const std::uint64_t texels = build.patch.spec.patch_texels;
        return with_base.size() < least_heightmaps ||
               ledger->used() + texels * texels * 8 <= kBuildShare * ledger->budget();
    }

    // Whether the held heightmaps may be weighed again (make_room visits every one): every kRoomLook.
    bool room_look_due() const { return std::chrono::steady_clock::now() - room_looked >= kRoomLook; }

    // Lets go of the heightmaps whose key is above `above` (farther, or out of view), farthest first,
    // until the data is under kKeepShare of the budget, keeping `keep` at least.
    void make_room(double above, std::size_t keep) {
        room_looked = std::chrono::steady_clock::now();
        std::vector<std::pair<double, CellKey>> far;
        for (const CellKey cell : with_base) {
            const double key = key_of(patches.at(cell), cell, *grid);
            if (key > above) far.emplace_back(key, cell);
        }
        std::sort(far.begin(), far.end(), [](const auto& a, const auto& b) { return a.first > b.first; });
        const double target = kKeepShare * ledger->budget();
        for (std::size_t n = 0; n < far.size() && ledger->used() > target && with_base.size() > keep; ++n) {
            let_go_heightmap(far[n].second);
        }
    }

    // Drops a patch's heightmap (it shows its chunk points again) and queues it to be built when near.
    void let_go_heightmap(CellKey cell) {
        Patch& p = patches.at(cell);
        modify(cell, p, [&] {
            p.base.reset(), p.shown.reset();
            p.base_is_cnn = false;
        });
        changed_patch(cell, p);
        ++let_go;
        p.ready = false;
        push_ready(cell, p);
    }

    void count_kind(const Patch& p, int delta) {
        if (p.base) (p.base_is_cnn ? shown_cnn : shown_linear) += delta;
    }

    // The drawable content of block `b` (listed again when it changed): its cells' heightmaps, and its chunk
    // points, those of the cells that show a heightmap left out (a copy, counted in the ledger while listed).
    void list_block(CellBlocks::Block& b) {
        if (!b.changed) return;
        b.shown.clear(), b.chunk_points.clear();
        bool any_shown = false;
        for (const auto cell : b.cells[CellBlocks::Drawable]) {
            ++patch_visits;
            const Patch& p = patches.at(cell);
            if (p.shown) b.shown.push_back(p.shown), any_shown = true;
        }
        std::shared_ptr<const PointSet> drawn;
        if (b.chunks && !any_shown) {
            drawn = std::shared_ptr<const PointSet>(b.chunks, &b.chunks->set);
        } else if (b.chunks) {
            drawn = std::make_shared<const PointSet>(chunks_without(*b.chunks, [&](CellKey cell) {
                const Patch* p = patches.find(cell);
                return p && p->shown;
            }));
        }
        const std::uint64_t copy = drawn && drawn.get() != &b.chunks->set
                                       ? sizeof(PointSet) + drawn->points.capacity() * sizeof(render::PointAttr)
                                       : 0;
        ledger->add_patch_bytes(static_cast<std::int64_t>(copy) - static_cast<std::int64_t>(b.listed_bytes));
        b.listed_bytes = copy;
        if (drawn && !drawn->points.empty()) b.chunk_points.push_back(std::move(drawn));
        b.changed = false;
    }

    // A block's chunk points made again (read_block_chunks), in the ledger in place of the old.
    void set_chunks(CellBlocks::Block& b, std::shared_ptr<const BlockChunks> chunks) {
        const std::uint64_t before = b.chunks ? b.chunks->bytes() : 0;
        ledger->add_patch_bytes(static_cast<std::int64_t>(chunks->bytes()) - static_cast<std::int64_t>(before));
        b.chunks = std::move(chunks);
        b.changed = true;
    }

    static std::uint64_t bytes_of(const Patch& p) {
        std::uint64_t bytes = 0;
        if (p.base) bytes += heightmap_bytes(*p.base);
        if (p.shown && p.shown != p.base) bytes += heightmap_bytes(*p.shown);
        return bytes;
    }
};

Scheduler::Scheduler(const dataset::Dataset& dataset, SchedulerOptions options)
    : dataset_(dataset), options_(std::move(options)), has_rgb_(survey_has_rgb(dataset)),
      state_(std::make_unique<State>()) {
    const auto [ox, oy] = dataset::patch_grid_origin(dataset);
    grid_ = std::make_unique<lidarscout::PatchGrid>(ox, oy);
    State& s = *state_;
    s.grid = grid_.get();
    s.build.patch.min_points = options_.min_points;
    s.least_heightmaps = options_.least_heightmaps;
    s.build.patch.has_rgb = has_rgb_;
    s.build.footprints = tile_footprints(dataset);
    s.build.batch = options_.cnn_batch;
    s.z_min = dataset.bounds_m.min_z, s.z_max = dataset.bounds_m.max_z;
    const double pad = s.build.patch.spec.pad_m();
    const auto dense = [&](const dataset::DatasetTile& t) {
        return t.chunk_points > 0 && !t.bounds_m.empty() && bounds_fit_data(t, *grid_, pad);
    };
    s.sparse.resize(dataset.tiles.size());
    dataset::Bounds extent;  // of the dense tiles: the cell blocks' grid
    std::vector<CellKey> candidates;  // (gathered, then the table made at its size: no rehash of a country's)
    for (std::uint32_t i = 0; i < dataset.tiles.size(); ++i) {
        const auto& t = dataset.tiles[i];
        s.loadable += t.chunk_points > 0;
        s.sparse[i] = !dense(t);
        if (s.sparse[i]) continue;
        extent.extend(t.bounds_m);
        for_cells(t.bounds_m, *grid_, 0.0, [&](CellKey c) { candidates.push_back(c); });
    }
    sort_cells(candidates);
    candidates.erase(std::unique(candidates.begin(), candidates.end()), candidates.end());
    s.patches.reserve(candidates.size());
    for (const CellKey c : candidates) {
        Patch& p = s.patches[c];
        p.candidate = p.counted = true;
    }
    candidates = {};
    s.blocks = CellBlocks(*grid_, extent, s.z_min, s.z_max);
    std::vector<std::uint32_t> every(dataset.tiles.size());
    std::iota(every.begin(), every.end(), 0u);
    s.for_window_cells_of(every, dataset.tiles, [](Patch& p, CellKey, int n) { p.deps += n; });
    s.candidates = s.patches.size();
    s.network_pending = options_.cnn;

    s.ledger = std::make_shared<MemoryLedger>(
        options_.memory_budget ? options_.memory_budget : default_memory_budget(), grid_.get());
    s.count_table();
    overview_core_bytes_ = s.table_bytes + s.patches.size() * PatchGrid::kCellOverheadBytes +
                           dataset.chunk_point_count * (sizeof(GridPoint) + sizeof(render::PointAttr));
    residency_ = std::make_unique<Residency>(dataset_, *grid_, residency_options());
    dataset::ChunkPointLoaderOptions loading = options_.loader;
    loading.release_overview = true;  // the grid holds a sidecar's chunk points from then on
    loader_ = std::make_unique<dataset::ChunkPointLoader>(dataset_, *grid_, loading);
    loader_->on_tile_done([this](std::span<const std::uint32_t> tiles, std::span<const CellKey> cells) {
        on_tiles_done(tiles, cells);
    });
    if (options_.camera) {
        set_camera(*options_.camera);
    } else if (!dataset.bounds_m.empty()) {  // until a camera comes: the middle, not the tiles nearest (0, 0)
        loader_->set_focus(dataset.bounds_m.centre_x(), dataset.bounds_m.centre_y());
    }
    loader_->start();
    for (unsigned i = 0; i < std::clamp(options_.heightmap_threads, 1u, max_threads()); ++i) {
        threads_.emplace_back([this] { heightmap_worker(); });
    }
    if (options_.cnn) threads_.emplace_back([this] { cnn_worker(); });
    threads_.emplace_back([this] { loader_watch(); });
    if (options_.full_res) {
        residency_->set_min_screen_fraction(std::max(options_.residency.min_screen_fraction, kLoadingScreenFraction));
        residency_->start();
    }
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
    r.ledger = state_->ledger;
    r.decode_threads =
        options_.decode_threads ? options_.decode_threads : std::max(1u, std::thread::hardware_concurrency());
    r.has_rgb = has_rgb_;
    r.patch_texels = state_->build.patch.spec.patch_texels;
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

void Scheduler::on_tiles_done(std::span<const std::uint32_t> tiles, std::span<const CellKey> cells) {
    State& s = *state_;
    const bool any_sparse = std::any_of(tiles.begin(), tiles.end(), [&](std::uint32_t t) { return s.sparse[t]; });
    std::vector<char> sparse_cell(cells.size());  // the cell holds a sparse tile's point (its cells are its points')
    if (any_sparse) {
        for (std::size_t i = 0; i < cells.size(); ++i) {
            grid_->read_points(cells[i], [&](std::span<const GridPoint> points) {
                sparse_cell[i] = std::any_of(points.begin(), points.end(), [&](const GridPoint& g) {
                    return s.sparse[g.tile];
                });
            });
        }
    }
    {
        std::lock_guard lock(s.mutex);
        for (std::size_t i = 0; i < cells.size(); ++i) {
            if (!sparse_cell[i]) continue;
            Patch& p = s.patches[cells[i]];
            if (!p.candidate) s.add_sparse_candidate(cells[i], p);
        }
        s.count_table();
        s.for_window_cells_of(tiles, dataset_.tiles, [&](Patch& p, CellKey cell, int n) {
            if ((p.deps -= n) == 0) s.push_ready(cell, p);
        });
    }
    if (show_chunk_points(cells, tiles.size(), false)) {
        // (every tile's in: the cells' spare capacity, up to an eighth of the grid: PatchGrid::add_in_cells, goes)
        grid_->shrink_to_fit();
        trim_heap();
    }
    s.wake.notify_all();
    for (const std::uint32_t tile : tiles) emit({SchedulerEvent::Kind::TileDone, tile, {}});
}

bool Scheduler::show_chunk_points(std::span<const CellKey> cells, std::size_t tiles, bool now) {
    State& s = *state_;
    std::lock_guard batch(chunks_mutex_);
    pending_cells_.insert(pending_cells_.end(), cells.begin(), cells.end());
    pending_tiles_ += tiles, arrived_tiles_ += tiles;
    now = now || arrived_tiles_ == s.loadable;  // (the last batch: at once)
    const auto t = std::chrono::steady_clock::now();
    if (pending_tiles_ == 0 ||
        (!now && cells.size() < kChunkBatchCells && t - chunks_read_ < kChunkReading)) {
        return false;
    }
    chunks_read_ = t;
    // The blocks these cells lie in are read again from the grid (each from the cells its last reading had and
    // these), by the shared pool's threads outside the state lock: they were most of this thread's work while a
    // country's chunk points came in, and the loader's thread is what the last waits for.
    struct BlockWork {
        CellKey block;
        std::vector<CellKey> cells;
        std::shared_ptr<const BlockChunks> chunks;
    };
    std::vector<BlockWork> work;
    const std::vector<CellKey> pending = std::exchange(pending_cells_, {});
    {
        std::vector<std::pair<CellKey, CellKey>> by_block;  // (block, cell)
        by_block.reserve(pending.size());
        for (const CellKey cell : pending) by_block.emplace_back(CellBlocks::key_of_cell(cell), cell);
        std::sort(by_block.begin(), by_block.end(), [](const auto& a, const auto& b) {
            return std::pair(cell_order(a.first), cell_order(a.second)) <
                   std::pair(cell_order(b.first), cell_order(b.second));
        });
        std::lock_guard lock(s.mutex);
        for (const auto& [block, cell] : by_block) {
            if (work.empty() || work.back().block != block) {
                work.push_back({block, {}, nullptr});
                if (const auto& had = s.blocks.block_of(cell).chunks) work.back().cells = had->cells;
            }
            work.back().cells.push_back(cell);
        }
    }
    const auto read = [&](std::size_t i) {
        BlockWork& w = work[i];
        sort_cells(w.cells);
        w.cells.erase(std::unique(w.cells.begin(), w.cells.end()), w.cells.end());
        auto chunks = read_block_chunks(*grid_, w.block, w.cells);
        if (!has_rgb_) paint_uncoloured(std::span(&chunks->set, 1));
        w.chunks = std::move(chunks);
    };
    constexpr std::size_t kPoolFrom = 8;  // blocks (a tile's cells are in one to four; a sidecar's batch thousands)
    if (work.size() >= kPoolFrom) {
        ThreadPool::shared().for_each(work.size(), read);
    } else {
        for (std::size_t i = 0; i < work.size(); ++i) read(i);
    }
    std::lock_guard lock(s.mutex);
    for (auto& w : work) s.set_chunks(s.blocks.block_of(w.cells.front()), std::move(w.chunks));
    for (const CellKey cell : pending) {
        Patch& p = s.patches[cell];
        s.modify(cell, p, [&] { p.chunk = true; });
        s.changed_patch(cell, p);
    }
    s.count_table();
    s.tiles_done += std::exchange(pending_tiles_, 0);  // (a tile is done once its chunk points are shown)
    return s.tiles_done == s.loadable;
}

void Scheduler::heightmap_worker() {
    lower_thread_priority(options_.residency.decode_nice);  // background work: frames first
    State& s = *state_;
    std::unique_lock lock(s.mutex);
    while (true) {
        s.wake.wait_for(lock, kRoomLook,
                        [&] { return s.stopping || s.blocks.size(CellBlocks::Ready) > 0 || !s.restyle.empty(); });
        if (s.stopping) return;
        if (s.ledger->used() > kTrimShare * s.ledger->budget() && s.room_look_due()) {
            s.make_room(-1.0, s.least_heightmaps);  // the farthest, down to the least held
        }
        if (s.blocks.size(CellBlocks::Ready) == 0 && s.restyle.empty()) continue;
        if (!s.restyle.empty()) {  // the user changed the surface: before any new heightmap
            restyle_some(lock);
            continue;
        }
        double key = 0;
        const CellKey cell = *s.take_next(CellBlocks::Ready, &key);
        // A patch out of view waits while the tiles in view decode: their points improve the
        // picture, its heightmap does not (a country's patches would hold the cores for minutes).
        if (key >= kOutOfView && options_.full_res && !residency_->idle()) {
            s.blocks.add(CellBlocks::Ready, cell);  // back in its block
            s.wake.wait_for(lock, kOutOfViewWait);
            continue;
        }
        // No room: the heightmaps farther than this one make it, else it waits for the camera to move (or
        // for room: the residency's releases, a larger budget).
        if (!s.room_for_heightmap()) {
            const bool due = s.room_look_due();
            if (due) s.make_room(key, s.least_heightmaps - std::min(s.least_heightmaps, kRoomBatch));
            if (!s.room_for_heightmap()) {
                s.blocks.add(CellBlocks::Ready, cell);
                if (!due) {  // weighed a moment ago: again when due
                    s.wake.wait_until(lock, s.room_looked + kRoomLook, [&] { return s.stopping; });
                    continue;
                }
                const std::uint64_t version = s.no_room_version = s.camera_version;  // the view is done
                s.wake.wait_for(lock, kRoomLook, [&] { return s.stopping || s.camera_version != version; });
                continue;
            }
        }
        s.no_room_version = kNoVersion;
        ++s.in_flight;
        lock.unlock();
        auto h = linear_heightmap(*grid_, cell, s.build.patch);
        if (h && !mask_to_footprints(*h, s.build.footprints)) h.reset();
        lock.lock();
        --s.in_flight;
        Patch& p = s.patches[cell];
        if (!std::exchange(p.linear_tried, true)) ++s.linear_tried;  // counted once: a heightmap let go comes again
        if (!h) continue;
        if (!std::exchange(p.linear_made, true)) ++s.linear_made;
        if (!p.base_is_cnn) {
            s.modify(cell, p, [&] { p.base = share(std::move(*h)); });
            s.update_shown(cell, p, residency_->detail(cell).get());
        }
        if (s.network || s.network_pending) {
            s.blocks.add(CellBlocks::CnnReady, cell);
            s.wake.notify_all();
        }
        lock.unlock();
        emit({SchedulerEvent::Kind::LinearHeightmap, 0, cell});
        lock.lock();
    }
}

void Scheduler::restyle_some(std::unique_lock<RankedMutex>& lock) {
    constexpr std::size_t kChunk = 16;  // patches laid over per turn of the lock
    State& s = *state_;
    const Surface surface = s.surface;
    struct Job {
        CellKey cell;
        std::shared_ptr<const PatchHeightmap> base, shown;
    };
    std::vector<Job> jobs;
    while (!s.restyle.empty() && jobs.size() < kChunk) {
        const CellKey cell = s.restyle.back();
        s.restyle.pop_back();
        const Patch* p = s.patches.find(cell);
        if (p && p->base) jobs.push_back({cell, p->base, nullptr});
    }
    s.restyling += jobs.size();
    lock.unlock();
    for (auto& job : jobs) {
        const auto detail = residency_->detail(job.cell);
        job.shown = detail ? share(overlay_detail(*job.base, *detail, surface)) : job.base;
    }
    lock.lock();
    s.restyling -= jobs.size();
    for (auto& job : jobs) {
        Patch& p = s.patches[job.cell];
        // Another surface since, or a new base or detail laid over meanwhile (update_shown): theirs is newer.
        if (s.surface != surface || p.base != job.base || (p.shown && p.shown->surface == surface)) continue;
        s.set_shown(job.cell, p, std::move(job.shown));
    }
}

void Scheduler::set_surface(Surface surface) {
    State& s = *state_;
    {
        std::lock_guard lock(s.mutex);
        if (s.surface == surface) return;
        s.surface = surface;
        s.restyle = residency_->detail_cells();  // the details' lock alone, under ours (the lock order)
    }
    s.wake.notify_all();
}

Surface Scheduler::surface() const {
    std::lock_guard lock(state_->mutex);
    return state_->surface;
}

// With SchedulerOptions::network_asks_room: waits for set_network_room's answer; without room, the network is
// not loaded (LibTorch's 150-250 MiB go to the data) and one note says so.
bool Scheduler::network_has_room() {
    if (!options_.network_asks_room) return true;
    State& s = *state_;
    std::unique_lock lock(s.mutex);
    while (!s.stopping && s.network_room < 0) s.wake.wait_for(lock, std::chrono::milliseconds(50));
    if (s.stopping) return false;
    if (s.network_room > 0) return true;
    s.network_pending = false;
    s.network_declined = true;
    s.blocks.clear(CellBlocks::CnnReady);
    s.notes.push_back(network_declined_note(dataset_.tiles.size()));
    return false;
}

void Scheduler::set_network_room(bool room) {
    std::lock_guard lock(state_->mutex);
    state_->network_room = room ? 1 : 0;
}

void Scheduler::cnn_worker() {
    lower_thread_priority(options_.residency.decode_nice);  // background work: frames first
    State& s = *state_;
    {
        // LibTorch's start-up (dlopen, ~0.5-1 s of CPU, holding the dynamic loader's lock that
        // new threads need) waits until there is work for it: the first linear heightmap. Loaded
        // at once, it delayed the first frame of chunk points from 0.13 s to 0.9 s.
        std::unique_lock lock(s.mutex);
        while (!s.stopping && s.blocks.size(CellBlocks::CnnReady) == 0 && !loader_->finished()) {
            s.wake.wait_for(lock, std::chrono::milliseconds(50));
        }
        if (s.stopping) return;
    }
    if (!network_has_room()) return;
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
        s.blocks.clear(CellBlocks::CnnReady);
        return;
    }
    s.network = std::move(network);
    ThreadPool pool(1);
    while (true) {
        s.wake.wait(lock, [&] { return s.stopping || s.blocks.size(CellBlocks::CnnReady) > 0; });
        if (s.stopping) return;
        std::vector<CellKey> batch;
        while (batch.size() < std::max<std::size_t>(1, options_.cnn_batch)) {
            const auto cell = s.take_next(CellBlocks::CnnReady);
            if (!cell) break;
            if (s.patches.at(*cell).base) batch.push_back(*cell);  // else let go meanwhile: refined when built again
        }
        if (batch.empty()) continue;
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
        for (const auto cell : batch) s.cnn_tried += !std::exchange(s.patches[cell].cnn_tried, true);
        for (auto& h : built) {
            const CellKey cell = h.cell;
            Patch& p = s.patches[cell];
            if (!p.base) continue;  // let go while the network ran
            s.modify(cell, p, [&] {
                p.base = share(std::move(h));
                p.base_is_cnn = true;
            });
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
        show_chunk_points({}, 0, false);  // (what the last batches left, kChunkReading after the last reading)
        std::lock_guard lock(s.mutex);
        if (s.stopping) return;
    }
    show_chunk_points({}, 0, true);
    residency_->set_min_screen_fraction(options_.residency.min_screen_fraction);  // (kLoadingScreenFraction)
    // Tiles that never loaded: build what can be. A country has 500,000 patches: they are queued a
    // few thousand at a time, so that no frame waits for all of them.
    constexpr std::size_t kPatches = 4096;
    for (std::size_t first = 0;; first += kPatches) {
        {
            std::lock_guard lock(s.mutex);
            if (s.stopping || first >= s.patches.size()) break;
            const std::size_t end = std::min(s.patches.size(), first + kPatches);
            for (std::size_t i = first; i < end; ++i) s.push_ready(s.patches.key(i), s.patches.value(i));
        }
        s.wake.notify_all();
    }
    std::lock_guard lock(s.mutex);
    s.loader_finish_handled = true;  // every tile's part is in (no tile is done after the loader)
    s.wake.notify_all();
}

void Scheduler::show_detail(const std::vector<CellKey>& cells) {
    State& s = *state_;
    std::lock_guard lock(s.mutex);
    for (const auto cell : cells) {
        if (Patch* p = s.patches.find(cell)) s.update_shown(cell, *p, residency_->detail(cell).get());
    }
}

std::shared_ptr<const SceneSnapshot> Scheduler::snapshot() const {
    State& s = *state_;
    // All three only grow: the content (in view and out), the residency's, and the camera's (what is
    // in view). The residency's blocks are taken outside our lock (see the lock order in scheduler.hpp).
    const std::uint64_t residency = residency_->version();
    {
        std::lock_guard lock(s.mutex);
        if (s.snapshot && s.snapshot->version == s.version + residency + s.camera_version) return s.snapshot;
        // Only the content changed while chunk points still come in: the snapshot is kept for the interval,
        // or five times what making it took (it holds the lock the loader and heightmaps wait for).
        const auto age = std::chrono::steady_clock::now() - s.snapshot_made;
        if (s.snapshot && s.snapshot_camera == s.camera_version && s.tiles_done < s.loadable &&
            options_.content_snapshot_interval_s > 0 &&
            age < std::max(std::chrono::duration<double>(options_.content_snapshot_interval_s), 5 * s.snapshot_cost)) {
            return s.snapshot;
        }
    }
    LodBlocks full = residency_->blocks();  // as new as `residency` or newer
    std::lock_guard lock(s.mutex);
    auto snap = std::make_shared<SceneSnapshot>();
    const auto made = std::chrono::steady_clock::now();
    snap->version = s.version + residency + s.camera_version;
    if (s.snapshot) {  // (about as many as the last: one allocation, not a doubling's; page faults were 213 of the
                       // 341 samples of snapshots taken while a country loaded)
        snap->heightmaps.reserve(s.snapshot->heightmaps.size() + s.snapshot->heightmaps.size() / 8);
        snap->chunk_points.reserve(s.snapshot->chunk_points.size() + s.snapshot->chunk_points.size() / 8);
    }
    // The blocks in view only (all without a camera): a country has 500,000 patches.
    const std::uint64_t before = s.work();
    const auto add = [&](CellBlocks::Block& b) {
        s.list_block(b);
        snap->heightmaps.insert(snap->heightmaps.end(), b.shown.begin(), b.shown.end());
        snap->chunk_points.insert(snap->chunk_points.end(), b.chunk_points.begin(), b.chunk_points.end());
    };
    if (s.has_camera) {
        s.blocks.visit(CellBlocks::Drawable, [&](const dataset::Bounds& box) { return box_in_view(s.camera, box); },
                       add);
    } else {
        s.blocks.for_each(add);
    }
    snap->full_points = std::move(full);
    s.snapshot_visits = s.work() - before;
    s.snapshot = std::move(snap);
    s.snapshot_camera = s.camera_version;
    s.snapshot_made = std::chrono::steady_clock::now();
    s.snapshot_cost = s.snapshot_made - made;
    return s.snapshot;
}

std::shared_ptr<const PatchHeightmap> Scheduler::heightmap(lidarscout::CellKey cell) const {
    std::lock_guard lock(state_->mutex);
    const Patch* p = state_->patches.find(cell);
    return p ? p->shown : nullptr;
}

SchedulerStats Scheduler::stats() const {
    const State& s = *state_;
    SchedulerStats st;
    st.tiles = dataset_.tiles.size();
    st.chunk_points = {loader_->loaded() + loader_->failed(), loader_->total()};
    st.chunk_points_loaded = loader_->loaded();
    const auto loader_errors = loader_->errors();  // before our lock: the loader's own is taken
    const ResidencyStats r = residency_->stats();   // the same
    std::lock_guard lock(s.mutex);
    st.tiles_loaded = {s.tiles_done, s.loadable};
    st.linear = {s.linear_tried, s.candidates};
    if (s.network) st.cnn = {s.cnn_tried, s.linear_made};
    st.heightmaps_linear = s.shown_linear, st.heightmaps_cnn = s.shown_cnn;
    st.heightmap_jobs_pending =
        s.blocks.size(CellBlocks::Ready) + s.blocks.size(CellBlocks::CnnReady) + s.in_flight;
    st.heightmaps_let_go = s.let_go;
    st.surface_pending = s.restyle.size() + s.restyling;
    st.full_res = {r.wanted_full, r.wanted};
    st.full_res_nearest = r.largest_full;
    st.full_res_tiles = r.full_tiles;
    st.coarse_tiles = r.coarse_tiles;
    st.full_res_points = r.full_points;
    st.lod_points = r.lod_points;
    st.full_res_released = r.released;
    st.full_res_loads = r.loads;
    st.bytes_full_res = r.bytes;
    st.bytes_decoding = r.decoding_bytes;
    st.bytes_used = s.ledger->outside_residency() + r.bytes + r.decoding_bytes;
    st.peak_bytes_used = std::max(r.peak_bytes, st.bytes_used);
    st.memory_budget = r.budget;
    st.snapshot_visits = s.snapshot_visits, st.job_visits = s.job_visits;
    st.look_visits = r.look_visits, st.tiles_in_view = r.in_view;
    st.notes = s.notes;
    st.network_declined = s.network_declined;
    st.overview_core_bytes = overview_core_bytes_;
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
    // Jobs left for lack of room wait for the camera to move: the view is done.
    const bool waiting = s.no_room_version == s.camera_version;
    return s.loader_finish_handled && (s.blocks.size(CellBlocks::Ready) == 0 || waiting) &&
           s.blocks.size(CellBlocks::CnnReady) == 0 && s.in_flight == 0 && s.restyle.empty() && s.restyling == 0 &&
           !s.network_pending && (!options_.full_res || residency_->idle());
}

bool Scheduler::points_loading() const { return options_.full_res && !residency_->idle(); }

}  // namespace lidarscout::viewer
