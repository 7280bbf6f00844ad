// SessionOpening: open_dataset on a thread of its own, its per-tile callbacks gathered under a
// lock for the window, then the Scheduler built on the dataset.
#include "viewer/session_opening.hpp"

#include <algorithm>
#include <exception>
#include <utility>

namespace lidarscout::viewer {

SessionOpening::SessionOpening(std::vector<std::string> paths, SessionOptions options)
    : thread_([this, paths = std::move(paths), options = std::move(options)] { run(paths, options); }) {}

SessionOpening::~SessionOpening() {
    cancel_ = true;
    if (thread_.joinable()) thread_.join();
}

void SessionOpening::run(const std::vector<std::string>& paths, const SessionOptions& options) {
    dataset::DatasetOptions d;
    d.crs = options.crs;
    d.cancel = &cancel_;
    d.sources_found = [this](std::span<const dataset::TileSource> sources) {
        std::vector<dataset::Bounds> placed;  // a catalog's tiles, where its items say (CRS lookups outside the lock)
        for (const auto& s : sources) {
            if (const auto b = s.item ? dataset::catalog_footprint(*s.item) : std::nullopt) placed.push_back(*b);
        }
        std::lock_guard lock(mutex_);
        progress_.total = sources.size();
        for (const auto& b : placed) footprints_.push_back(b), progress_.extent.extend(b);
    };
    d.tile_read = [this](const dataset::DatasetTile& t) {
        std::lock_guard lock(mutex_);
        ++progress_.read;
        footprints_.push_back(t.bounds_m);
        if (t.tile.header.point_count > 0) progress_.extent.extend(t.bounds_m);
    };
    d.progress = [this](std::size_t done, std::size_t total) {
        std::lock_guard lock(mutex_);
        progress_.done = std::max(progress_.done, done);  // callbacks of several threads may cross
        progress_.total = total;
    };
    try {
        Session s;
        s.dataset = std::make_unique<dataset::Dataset>(dataset::open_dataset(paths, d));
        dataset::require_tiles(*s.dataset, "view");
        {
            std::lock_guard lock(mutex_);
            progress_.building = true;
        }
        s.cursor = std::make_unique<CursorReadout>(s.dataset->frame);
        s.places = std::make_unique<dataset::TileIndex>(*s.dataset);
        if (!cancel_) s.scheduler = std::make_unique<Scheduler>(*s.dataset, options.scheduler);
        std::lock_guard lock(mutex_);
        session_ = std::move(s);
    } catch (const Error& e) {
        std::lock_guard lock(mutex_);
        error_ = e;
    } catch (const std::exception& e) {  // out of memory, a thread that could not start
        std::lock_guard lock(mutex_);
        error_ = Error(std::string("view: opening failed: ") + e.what());
    }
    finished_ = true;
}

OpeningProgress SessionOpening::progress() const {
    std::lock_guard lock(mutex_);
    return progress_;
}

void SessionOpening::footprints(std::vector<dataset::Bounds>& out) const {
    std::lock_guard lock(mutex_);
    out.insert(out.end(), footprints_.begin() + static_cast<std::ptrdiff_t>(std::min(out.size(), footprints_.size())),
               footprints_.end());
}

Session SessionOpening::take() {
    if (thread_.joinable()) thread_.join();
    std::lock_guard lock(mutex_);
    if (error_) throw *error_;
    if (!session_) throw Error("view: the dataset was taken already");
    Session s = std::move(*session_);
    session_.reset();
    return s;
}

}  // namespace lidarscout::viewer
