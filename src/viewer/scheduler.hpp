// The viewer's streaming scheduler: all background work for an opened dataset, re-prioritised
// as the camera moves.
//   - chunk points: the ChunkPointLoader, its focus the ground point the camera looks at;
//   - heightmaps: a patch's heightmap is built as soon as every tile overlapping its window
//     (the cell +- the recon padding) has its chunk points in the grid, visible and near
//     patches first (those out of view wait while the residency decodes for the view); linear
//     first, then the network in batches when a model is loaded (its heightmap replaces the
//     linear one). A tile whose header bounds are far larger than its data could fill counts only
//     the cells its chunk points fell in, and those wait for every tile's chunk points: memory
//     follows the data, never the bounding box;
//   - full resolution with level of detail: the Residency (residency.hpp, its own thread and
//     lock) decodes the tiles in view, the one that improves the picture most per byte first,
//     into LOD blocks (point_lod.hpp), within a memory budget that covers everything the
//     scheduler holds; every tile's points are folded into the heightmaps and textures of the
//     patches it covers (patch_detail.hpp), and a released tile keeps its coarse levels.
// snapshot() gives what is ready now for the current camera, cheap enough to take every frame:
// the patches of the blocks in view (viewer/cell_blocks.hpp) and the residency's blocks (patches
// that changed out of view join it at the next camera move, so that a still view's snapshot stays
// the same once its picture is done); stats() the counters. Per-frame and per-tick work follows
// what is in view and what changed, not the dataset's size (the next heightmap job is found best
// first over the blocks, the residency's tiles in view and the loader's next tile through a tile
// index), so a country of tiles draws as fast as a county.
//
// Lock order, so that a frame never waits for work proportional to the dataset (ranked mutexes,
// core/ranked_mutex.hpp: a thread breaking it stops the process, in every build):
//   1. the scheduler's state lock (State::mutex) may be held while taking only the residency's
//      details lock (Residency::detail, a leaf held for a lookup) or reading its atomics
//      (version, idle); never the residency's own lock nor the loader's;
//   2. the residency calls its hooks (on_detail, on_tile) without its own lock, so they may take
//      the state lock; what each holds is in a MemoryLedger they share (atomics, no lock);
//   3. the loader calls on_tile_done (on_tiles_done here) without its locks; set_focus takes a lock of its own only;
//      on_tiles_done takes its own batch lock (chunks_mutex_, before the state lock: never taken under it).
#pragma once

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <functional>
#include <memory>
#include <mutex>
#include <optional>
#include <span>
#include <string>
#include <thread>
#include <vector>

#include "core/error.hpp"
#include "dataset/chunk_point_loader.hpp"
#include "dataset/dataset.hpp"
#include "core/patch_grid.hpp"
#include "render/camera.hpp"
#include "viewer/heightmap_builder.hpp"
#include "viewer/residency.hpp"
#include "viewer/scene_snapshot.hpp"
#include "viewer/visibility.hpp"

namespace lidarscout::viewer {

// What happened, for hooks and tests (called from worker threads, outside the scheduler's lock).
struct SchedulerEvent {
    enum class Kind { TileDone, LinearHeightmap, CnnHeightmap, FullResLoaded, FullResReleased };
    Kind kind = Kind::TileDone;
    std::uint32_t tile = 0;     // TileDone, FullRes*
    lidarscout::CellKey cell{};    // *Heightmap
};

struct SchedulerOptions {
    std::uint64_t memory_budget = 0;  // bytes of everything held (0 = a quarter of the RAM)
    std::optional<render::Camera> camera;  // the first camera (set before any read starts)
    bool cnn = true;                  // refine with the network when a model can be loaded
    // The network is loaded only once set_network_room says there is room for it (the viewer, from its process
    // budget); without, it is loaded when the first heightmap wants it.
    bool network_asks_room = false;
    std::string model_path;           // empty: nn::default_model_path()
    std::size_t cnn_batch = 16;
    bool full_res = true;             // decode the tiles in view (residency.hpp)
    ResidencyOptions residency;       // LOD and priorities; the budget, threads and hooks are set from here
    std::size_t min_points = kViewerMinPoints;
    // The nearest heightmaps held whatever the budget (a country's chunk points alone may fill it): about
    // a view's worth. Beyond them heightmaps are built within the budget, the farthest let go for nearer.
    std::size_t least_heightmaps = 512;
    unsigned heightmap_threads = 1;   // linear heightmap workers
    // While chunk points still come in, a snapshot for the current camera is kept this long before one
    // with the newer content is made (0: always the newest). Making one visits every patch in view:
    // a country's 760,000 each frame, with their release, held a core while its chunk points loaded.
    double content_snapshot_interval_s = 0;
    unsigned decode_threads = 0;      // full-resolution decoding (0 = all cores)
    dataset::ChunkPointLoaderOptions loader;
    // Called for every event, from the thread that caused it; may block (tests use this to
    // hold the loader back).
    std::function<void(const SchedulerEvent&)> on_event;
};

struct StageProgress {
    std::uint64_t done = 0, total = 0;
};

struct SchedulerStats {
    std::size_t tiles = 0;
    StageProgress tiles_loaded;        // tiles whose chunk points are in
    StageProgress chunk_points;        // chunk points read (loaded or failed) / all
    std::uint64_t chunk_points_loaded = 0;
    StageProgress linear;              // patches tried / patches the tiles cover
    StageProgress cnn;                 // patches refined / patches with a linear heightmap (0 total: no model)
    std::size_t heightmaps_linear = 0, heightmaps_cnn = 0;  // patches showing each kind
    std::size_t heightmap_jobs_pending = 0;                   // queued or running (linear and network)
    std::size_t heightmaps_let_go = 0;  // heightmaps dropped to keep the budget (built again when near)
    std::size_t surface_pending = 0;   // patches still to be laid over again for the surface set last
    StageProgress full_res;            // wanted tiles resident / wanted tiles
    bool full_res_nearest = false;     // the wanted tile of most screen coverage is resident (ResidencyStats)
    std::size_t full_res_tiles = 0, coarse_tiles = 0;  // tiles held at full resolution; at coarse levels only
    std::uint64_t full_res_points = 0, lod_points = 0;  // points of the full tiles; of every tile held
    std::size_t full_res_released = 0;  // tiles released so far
    std::size_t full_res_loads = 0;     // tile decodes started so far (whole or in part)
    std::uint64_t bytes_used = 0, bytes_full_res = 0, memory_budget = 0;
    std::uint64_t bytes_decoding = 0;   // of bytes_used: what the tile being decoded may still add and its scratch
    std::uint64_t peak_bytes_used = 0;  // highest bytes_used seen, a decoding tile included
    // The bookkeeping's work, for tests that check it follows the view, not the dataset: patches, cell
    // blocks and index nodes examined by the last snapshot built and the last choice of a heightmap
    // job; tile index nodes and tiles examined by the residency's last look, and the tiles it found
    // in view.
    std::uint64_t snapshot_visits = 0, job_visits = 0, look_visits = 0;
    std::size_t tiles_in_view = 0;
    std::uint64_t overview_core_bytes = 0;  // what every chunk point and the patch table will hold (estimate)
    bool network_declined = false;          // set_network_room said no room: the network not loaded
    std::vector<std::string> notes;     // e.g. "no heightmap network: linear heightmaps"
    std::vector<ErrorRecord> errors;    // what could not be read or computed: file, offset, cause
};

// A quarter of the machine's RAM (1 GiB when unknown).
std::uint64_t default_memory_budget();

class Scheduler {
public:
    // `dataset` must outlive the scheduler. Starts the background work at once.
    Scheduler(const dataset::Dataset& dataset, SchedulerOptions options = {});
    ~Scheduler();  // cancels and joins
    Scheduler(const Scheduler&) = delete;
    Scheduler& operator=(const Scheduler&) = delete;

    // Re-prioritises everything for this camera (cheap; call every frame).
    void set_camera(const render::Camera& camera);
    // Whether the network would leave full resolution room (SchedulerOptions::network_asks_room): the latest
    // answer counts when the network is about to load.
    void set_network_room(bool room);
    // Changes the memory budget (bytes; 0 = the default).
    void set_memory_budget(std::uint64_t bytes);
    // What the heightmaps show where full-resolution points were read: every point, or the bare
    // earth of a ground filter (patch_detail.hpp). The patches with detail are laid over again in
    // the background (a few at a time, none under the frame); until then they show the old surface,
    // which the frame tints (PatchHeightmap::view).
    void set_surface(Surface surface);
    Surface surface() const;

    // What is ready now; shares data with the scheduler (no points or heightmaps copied).
    std::shared_ptr<const SceneSnapshot> snapshot() const;
    SchedulerStats stats() const;

    const dataset::Dataset& dataset() const { return dataset_; }
    const lidarscout::PatchGrid& grid() const { return *grid_; }
    bool has_rgb() const { return has_rgb_; }
    // The heightmap shown now for `cell` (null when none).
    std::shared_ptr<const PatchHeightmap> heightmap(lidarscout::CellKey cell) const;
    // True when no work is left for the current camera (chunk points in, every heightmap
    // built, wanted tiles resident or over budget).
    bool idle() const;
    // True while full-resolution points for the current camera are still being decoded (a
    // picture drawn now is soon out of date).
    bool points_loading() const;

    // The point on the ground (at the dataset's mean height) the camera looks at.
    static std::pair<double, double> look_at_ground(const render::Camera& camera, const dataset::Bounds& bounds);

private:
    struct State;
    void on_tiles_done(std::span<const std::uint32_t> tiles, std::span<const lidarscout::CellKey> cells);
    // The chunk points of `cells` (of `tiles` tiles) into their blocks' sets, with those left by the batches
    // before: now when `now`, for the last batch or a large one, else once kChunkReading passed since the last
    // reading (the loader's watch asks too). Their tiles count as done then; true when that made every tile done.
    bool show_chunk_points(std::span<const lidarscout::CellKey> cells, std::size_t tiles, bool now);
    void heightmap_worker();
    void restyle_some(std::unique_lock<RankedMutex>& lock);
    void cnn_worker();
    bool network_has_room();
    void loader_watch();
    void show_detail(const std::vector<lidarscout::CellKey>& cells);
    ResidencyOptions residency_options();
    void emit(const SchedulerEvent& event) const;

    const dataset::Dataset& dataset_;
    SchedulerOptions options_;
    bool has_rgb_ = true;
    std::unique_ptr<lidarscout::PatchGrid> grid_;
    std::uint64_t overview_core_bytes_ = 0;  // SchedulerStats::overview_core_bytes
    std::unique_ptr<State> state_;
    // The blocks' chunk points read again one reading at a time (each from the cells its last held), and the
    // cells whose chunk points wait for the next reading (show_chunk_points).
    std::mutex chunks_mutex_;
    std::vector<lidarscout::CellKey> pending_cells_;
    std::size_t pending_tiles_ = 0, arrived_tiles_ = 0;  // the tiles of those cells; of every batch so far
    std::chrono::steady_clock::time_point chunks_read_{};
    std::unique_ptr<Residency> residency_;
    std::unique_ptr<dataset::ChunkPointLoader> loader_;
    std::vector<std::thread> threads_;
};

}  // namespace lidarscout::viewer
