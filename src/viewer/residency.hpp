// Full-resolution residency with level of detail, the part of the viewer's scheduler that
// decides which tiles' points are held: every visible tile is wanted, and the one whose decoding
// improves the picture most per byte comes first (its screen-space error: the spacing shown
// now, heightmap texels or coarse levels, in pixels at its nearest distance, times its screen
// coverage, per byte). Decoded tiles become LOD blocks (point_lod.hpp) and fold their points into
// the patch detail (patch_detail.hpp). When memory runs short, the tiles worth least per
// byte (out of view first, least recently seen first) drop to their coarse levels, then to
// nothing. A tile is decoded in pieces of whole chunks, those in view and nearest first, one
// piece per decoding thread at a time, each shown as soon as it is in; when no tile fits whole,
// the best one is loaded in part, as many pieces as there is room for, and decoded again when the
// camera moves to parts of it those pieces do not cover. A load happens only when it is worth
// more than what it displaces, and only when all it will hold fits: its points, its blocks' and
// details' bookkeeping, and what its decoding threads hold meanwhile (decode_memory.hpp: smaller
// pieces when room is short). Released blocks count until the last snapshot holding them is
// gone, and freed memory is handed back to the system (core/process_memory.hpp). So the memory
// budget (with what the rest of the scheduler holds) is never exceeded and loading converges.
// Its decisions are a class of their own, without threads (residency_policy.hpp); this one runs
// them on its own thread under its own lock, decodes, and calls its hooks without that lock held.
#pragma once

#include <atomic>
#include <condition_variable>
#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <set>
#include <string>
#include <thread>
#include <vector>

#include "core/error.hpp"
#include "core/ranked_mutex.hpp"
#include "core/throttle.hpp"
#include "dataset/dataset.hpp"
#include "core/patch_grid.hpp"
#include "render/camera.hpp"
#include "viewer/decode_memory.hpp"
#include "viewer/memory_ledger.hpp"
#include "viewer/point_lod.hpp"
#include "viewer/residency_policy.hpp"
#include "viewer/patch_detail.hpp"

namespace lidarscout::viewer {

struct ResidencyOptions {
    std::uint64_t memory_budget = 1ull << 30;  // bytes, what `ledger` counts outside the residency included
    unsigned decode_threads = 1;
    int decode_nice = 5;             // decoding threads run this much nicer than the caller
    bool has_rgb = true;
    int patch_texels = 64;           // detail texels per patch side
    double block_m = 80;             // LOD block side
    double coarse_spacing_m = 2;     // the finest level a released tile keeps
    double hysteresis = 1.25;        // a load must be worth this much more than what it displaces
    double min_screen_fraction = 0;  // tiles covering less of the image are not wanted
    // Shared with the scheduler: the budget (memory_budget is ignored when set) and what the rest of
    // it holds (heightmaps, chunk points, grid). Null: a ledger of the residency's own.
    std::shared_ptr<MemoryLedger> ledger;
    // Cells whose detail changed (a tile was folded in).
    std::function<void(const std::vector<lidarscout::CellKey>&)> on_detail;
    // A tile decoded (loaded = true) or dropped to its coarse levels (false).
    std::function<void(std::uint32_t tile, bool loaded)> on_tile;
};

struct ResidencyStats {
    std::size_t full_tiles = 0, coarse_tiles = 0, released = 0;
    std::size_t loads = 0;  // tile decodes started (whole or in part)
    std::size_t wanted = 0, wanted_full = 0;  // visible tiles; those at full resolution
    bool largest_full = false;  // the visible tile of most screen coverage is at full resolution (the policy's)
    std::uint64_t full_points = 0, lod_points = 0;  // points held at full resolution; in every block
    std::uint64_t bytes = 0, bytes_full = 0, decoding_bytes = 0, peak_bytes = 0, budget = 0;
    std::vector<ErrorRecord> errors;  // tiles that could not be decoded
    std::size_t in_view = 0;                       // tiles in view at the last look
    std::uint64_t index_visits = 0, look_visits = 0;  // tile index nodes and tiles examined: in all; the last look
};

class Residency {
public:
    Residency(const dataset::Dataset& dataset, const lidarscout::PatchGrid& grid, ResidencyOptions options);
    ~Residency();  // stops and joins
    Residency(const Residency&) = delete;
    Residency& operator=(const Residency&) = delete;

    void start();  // starts the worker (once the hooks can be called); throws Error when started already
    void stop();   // stops and joins the worker (a tile being decoded stops after its current piece)
    void set_camera(const render::Camera& camera);
    void set_budget(std::uint64_t bytes);
    // Tiles covering this share of the image or less are not wanted from the next look on.
    void set_min_screen_fraction(double fraction);

    // Every block held, full and coarse (shared, not copied).
    LodBlocks blocks() const;
    // The detail folded into cell `cell` (null when none).
    std::shared_ptr<const PatchDetail> detail(lidarscout::CellKey cell) const;
    // The cells that have detail (takes the details' lock alone, as detail() does).
    std::vector<lidarscout::CellKey> detail_cells() const;
    // Grows with every change of blocks() or detail.
    std::uint64_t version() const;
    ResidencyStats stats() const;
    // True when nothing is decoding and the last look at the current camera found nothing to do.
    bool idle() const;

private:
    using Level = ResidencyPolicy::Level;
    using Entry = ResidencyPolicy::Entry;
    struct Decoded {
        LodBlocks blocks;
        PatchDetails detail;
    };
    struct Job {
        std::uint32_t tile = 0;
        std::uint64_t cap = 0, piece_points = 0;  // bytes of points it may add; points per piece
    };

    void run();
    std::optional<Job> next_load(std::unique_lock<RankedMutex>& lock);
    // Bytes held: blocks, details, and blocks released but still alive (a snapshot being drawn).
    std::uint64_t held() const;
    // Tells the ledger what is held and decoding (under mutex_), for the scheduler's heightmaps; returns it.
    std::uint64_t publish_held() const;
    // Blocks dropped from the policy's entries: counted in held() until the last snapshot holding them is gone.
    void retire(const LodBlocks& blocks);
    bool prune_retired();  // forgets the retired blocks that are gone; true when any was
    bool drop(std::uint32_t tile);  // removes its entry, its blocks retired; false when it had none
    std::vector<std::uint32_t> release(const std::vector<std::uint32_t>& tiles);
    PointOrder decode_order() const;
    void refresh_idle();  // after a change of busy_, has_camera_, camera_version_ or checked_version_
    void load(const Job& job, const PointOrder& order, ThreadPool& pool);
    // Adds a decoded piece; `first` (cleared here, under the lock) drops the coarse levels held.
    std::vector<lidarscout::CellKey> commit(std::uint32_t tile, Decoded decoded, bool& first);
    void notify(const std::vector<std::uint32_t>& released, std::optional<std::uint32_t> loaded,
                const std::vector<lidarscout::CellKey>& cells) const;

    const dataset::Dataset& dataset_;
    const lidarscout::PatchGrid& grid_;
    ResidencyOptions options_;
    std::shared_ptr<MemoryLedger> ledger_;  // options_.ledger, or one of its own
    ResidencyPolicy policy_;  // the decisions and the table of tiles held (under mutex_; its tile index: the thread's)

    // Ranks 1 and 3 of the lock order in scheduler.hpp (the scheduler's state lock is 2).
    mutable RankedMutex mutex_{1, "residency"};
    std::condition_variable_any wake_;
    bool stopping_ = false, busy_ = false;
    render::Camera camera_;
    bool has_camera_ = false;
    std::uint64_t camera_version_ = 0, checked_version_ = ~0ull;
    std::uint64_t loading_version_ = 0;  // the camera version the tile being decoded was chosen for
    std::vector<std::pair<std::weak_ptr<const LodBlock>, std::uint64_t>> retired_;  // block, its bytes
    Throttle look_throttle_{std::chrono::milliseconds(100), 4096};  // looks at many tiles in view
    std::size_t last_in_view_ = 0;                     // tiles in view at the last look
    std::uint64_t index_visits_ = 0, last_look_visits_ = 0;  // tile index work: in all, at the last look
    std::set<std::uint32_t> folded_;  // tiles whose every point is in the details (not folded again on reload)
    // Changed under mutex_ and details_mutex_; read under either (detail() takes details_mutex_ alone,
    // a leaf lock held for a lookup: the scheduler asks while holding its own lock).
    std::map<lidarscout::CellKey, std::shared_ptr<const PatchDetail>> details_;
    mutable RankedMutex details_mutex_{3, "residency details"};
    std::uint64_t details_bytes_ = 0, decoding_bytes_ = 0, peak_ = 0, last_other_ = 0;
    std::atomic<std::uint64_t> version_{1};  // read without a lock (every snapshot asks)
    std::atomic<bool> idle_{true};           // idle(), kept by refresh_idle() under mutex_
    std::size_t released_ = 0, loads_ = 0;
    std::vector<ErrorRecord> errors_;
    mutable LodBlocks blocks_cache_;
    mutable std::uint64_t blocks_version_ = 0;
    std::thread thread_;
};

}  // namespace lidarscout::viewer
