// Progressive opening of the viewer's dataset: the tiles' metadata are read (and the Scheduler
// built on them) on a background thread, while the window keeps drawing. Until it is done the
// window shows what is known: how many tiles are read, failed and to go, and the footprints of
// the tiles read so far (a STAC catalog's every tile at once, where its items place them).
// A catalog whose items place every tile (dataset.hpp: DatasetOptions::placed) opens at once, its
// headers read on demand by the scheduler. A paged catalog (a STAC API search: pages of items linked by
// "next") opens its first page so, as the preview, while the later pages arrive (their footprints shown as
// they come), and opens again as a larger preview each time four times as many tiles arrived (a newer
// preview replaces the one before: preview()); the whole catalog opens once its last page is read.
// Another large catalog (each header a request) first opens the few tiles at its centre as a preview
// session of their own (chunk points and linear heightmaps, no full resolution), whose reads end before the
// rest of the headers are asked for: the window shows real terrain there within a second or two, long
// before every header is in.
// Destroying an opening that is not finished cancels it: files not yet started are not read,
// and the destructor waits only for the reads in progress.
#pragma once

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <cstddef>
#include <memory>
#include <mutex>
#include <optional>
#include <span>
#include <string>
#include <thread>
#include <vector>

#include "core/error.hpp"
#include "dataset/dataset.hpp"
#include "dataset/tile_index.hpp"
#include "viewer/cursor_readout.hpp"
#include "viewer/overview_cache.hpp"
#include "viewer/scheduler.hpp"

namespace lidarscout::viewer {

// An opened dataset and the scheduler working on it (the scheduler reads the dataset, so it is
// destroyed first).
struct Session {
    std::unique_ptr<dataset::Dataset> dataset;
    std::unique_ptr<dataset::TileIndex> places;  // its tiles by position (the tile boxes in view)
    std::unique_ptr<CursorReadout> cursor;
    // The sidecar kept for it (null: none): the scheduler's loader hands it records, and its write reads the
    // dataset, so it is destroyed after the one and before the other.
    std::shared_ptr<OverviewCache> overview_cache;
    std::unique_ptr<Scheduler> scheduler;

    bool open() const { return scheduler != nullptr; }
};

struct SessionOptions {
    std::string crs;                 // the frame's CRS; empty: the majority's
    SchedulerOptions scheduler;      // its camera, if set, is the first one
    // A catalog of more tiles than preview_above (0: never), whose items place every tile, first
    // opens its tiles within preview_radius_m of its centre (at most preview_tiles) as a preview; a paged
    // catalog its first page (whatever preview_above, but 0: no preview at all).
    std::size_t preview_above = 64;
    double preview_radius_m = 1000.0;
    std::size_t preview_tiles = 64;
    double preview_wait_s = 3.0;     // the longest the rest waits for the preview's chunk points
    std::size_t page_preview_most = 1024;  // a paged catalog's preview grows (4x at a time) up to these tiles
    // The overview sidecar kept for a remote dataset (viewer/overview_cache.hpp): used when there is one, else
    // the chunk points read kept for it; null: none.
    std::shared_ptr<OverviewCache> overview_cache;
};

// Where an opening stands, for a progress line.
struct OpeningProgress {
    std::size_t done = 0, total = 0;  // files tried / files found (0 while the paths are expanded)
    std::size_t read = 0;             // files read as tiles (done - read failed)
    dataset::Bounds extent;           // of the tiles read so far (each in its own CRS's metres)
    bool building = false;            // every file tried; the scheduler is being built
};

class SessionOpening {
public:
    // Starts opening `paths` at once (files, folders, tile lists, URLs).
    SessionOpening(std::vector<std::string> paths, SessionOptions options);
    ~SessionOpening();  // cancels what is not read yet, and waits for the reads in progress
    SessionOpening(const SessionOpening&) = delete;
    SessionOpening& operator=(const SessionOpening&) = delete;

    OpeningProgress progress() const;
    // The preview session of a large catalog's centre, or of a paged catalog's pages read so far (the latest),
    // once it is open (null before, and for a dataset without one). It stays valid for as long as the caller holds it.
    std::shared_ptr<const Session> preview() const;
    // Appends the footprints read since the last call (those after footprints.size()).
    void footprints(std::vector<dataset::Bounds>& out) const;
    // True when take() will not wait.
    bool finished() const { return finished_.load(); }
    // Waits until the paths are expanded (a catalog's every footprint known) or the opening ends, at
    // most `timeout`: a window's first frame can then show them. True when they are.
    bool wait_for_sources(std::chrono::milliseconds timeout) const;
    // Waits for the end; the session, or the Error that ended the opening (no readable tile,
    // a CRS that cannot be used). Once only.
    Session take();

private:
    void run(const std::vector<std::string>& paths, const SessionOptions& options);
    void note_sources(std::optional<std::size_t> sources, std::span<const std::optional<dataset::Bounds>> placed,
                      bool every_placed = false);
    std::shared_ptr<const Session> publish_preview(dataset::Dataset ds, const SessionOptions& options);
    bool open_page_preview(std::span<const dataset::TileSource> sources, const SessionOptions& options);
    void open_preview(std::span<const dataset::TileSource> sources,
                      std::span<const std::optional<dataset::Bounds>> placed, const SessionOptions& options);

    mutable std::mutex mutex_;
    OpeningProgress progress_;
    std::vector<dataset::Bounds> footprints_;
    std::optional<Session> session_;
    std::shared_ptr<const Session> preview_;
    std::optional<Error> error_;
    std::atomic<bool> cancel_{false}, finished_{false};
    mutable std::condition_variable sources_known_;  // under mutex_: progress_.total set, or finished
    bool sources_noted_ = false;
    bool every_footprint_noted_ = false;  // the items placed every source: a tile read adds no footprint
    std::thread thread_;
};

}  // namespace lidarscout::viewer
