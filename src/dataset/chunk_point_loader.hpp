// The chunk-point loader: reads the chunk points of every tile of a dataset in the
// background with many small reads in flight (io/batch_reader: io_uring, or a pread pool),
// nearest-to-the-focus tiles first, and bins them into a PatchGrid. The focus (a point of
// interest, later the camera) may move while it runs; tiles already started finish first,
// then the remaining ones follow the new order. A tile's points enter the grid together,
// when its last read completes, with colour scaled to 8 bits by one decision per tile
// (16-bit when any of its chunk points has a channel above 255). Cancellable; progress is
// readable at any time and a callback reports each finished tile.
// A dataset placed by its catalog (dataset.hpp) has its headers read here, in the same order: a
// thread reads those nearest the focus in growing batches (ensure_tiles), and a tile joins the reads
// once its header is in; a tile whose header cannot be read is one error and leaves the total.
#pragma once

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <functional>
#include <memory>
#include <mutex>
#include <span>
#include <string>
#include <thread>
#include <vector>

#include "core/error.hpp"
#include "core/patch_grid.hpp"
#include "io/batch_reader.hpp"

namespace lidarscout::dataset {

struct Dataset;

struct ChunkPointLoaderOptions {
    io::BatchReadOptions reads;      // back end, threads, reads in flight
    bool direct_io = false;          // open tiles with O_DIRECT (cold-cache measurements)
    std::size_t max_errors = 1000;   // keep at most this many errors
    unsigned header_threads = 16;    // a placed dataset's header reads in flight (DatasetOptions::io_threads)
    // Once the chunk points an overview sidecar holds are in the grid, let its records go
    // block by block (OverviewRelease): for a loader that is its dataset's only reader of them (the viewer's;
    // none while on_tile_records is set: whoever keeps records may read a sidecar's later).
    bool release_overview = false;
    // When set, called from reader threads with a tile's chunk points as read (raw records of its own format,
    // in chunk_point_locations order) once all of them are in, none failed, before the tile counts as done
    // (tiles_done); not for those an overview sidecar held. What the viewer keeps to write a remote dataset's
    // sidecar (viewer/overview_cache.hpp).
    std::function<void(std::uint32_t tile, std::vector<std::uint8_t>&& records)> on_tile_records;
};

class ChunkPointLoader {
public:
    // `dataset` and `grid` must outlive the loader. Tile ids in the grid are indices into
    // dataset.tiles.
    ChunkPointLoader(const Dataset& dataset, PatchGrid& grid, ChunkPointLoaderOptions options = {});
    ~ChunkPointLoader();  // cancels and waits
    ChunkPointLoader(const ChunkPointLoader&) = delete;
    ChunkPointLoader& operator=(const ChunkPointLoader&) = delete;

    // Tiles nearest to (x, y) in metres load first. May be called at any time.
    void set_focus(double x_m, double y_m);
    // Called from reader threads when tiles' chunk points are all in the grid: the tiles (a tile read, alone; an
    // overview sidecar's, many at once: a country's 152,100 in batches of growing size) with the grid cells
    // their points fell in (sorted, each once). Set before start().
    using TileDoneFn = std::function<void(std::span<const std::uint32_t> tiles, std::span<const CellKey> cells)>;
    void on_tile_done(TileDoneFn callback);

    void start();   // starts the background reads (once)
    void cancel();  // no new reads; those in flight complete
    // Until done or cancelled (returns at once when not started); rethrows a failure of the
    // loader itself (not of one file: those are in errors()).
    void wait();
    bool wait_for(std::chrono::milliseconds timeout);  // true when finished
    bool finished() const { return finished_.load(); }

    // Chunk points of all tiles (a placed tile's estimated from its item until its header is read).
    std::uint64_t total() const { return total_.load(); }
    std::uint64_t loaded() const { return loaded_.load(); }        // in the grid
    std::uint64_t failed() const { return failed_.load(); }        // unreadable or implausible
    std::size_t tiles_done() const { return tiles_done_.load(); }
    std::vector<ErrorRecord> errors() const;  // each with its file, offset and cause
    io::ReadBackend backend() const { return backend_used_.load(); }  // once finished

private:
    class Source;
    void run();

    std::atomic<std::uint64_t> total_{0};
    std::atomic<std::uint64_t> loaded_{0};
    std::atomic<std::uint64_t> failed_{0};
    std::atomic<std::size_t> tiles_done_{0};
    std::atomic<bool> finished_{false};
    std::atomic<io::ReadBackend> backend_used_{io::ReadBackend::Auto};
    std::unique_ptr<Source> source_;
    ChunkPointLoaderOptions options_;
    std::thread thread_;
    mutable std::mutex mutex_;
    std::condition_variable done_cv_;
    std::exception_ptr failure_;
};

}  // namespace lidarscout::dataset
