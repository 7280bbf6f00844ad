// SessionOpening: open_dataset on a thread of its own, its per-tile callbacks gathered under a
// lock for the window, then the Scheduler built on the dataset; a large catalog's central tiles
// opened before as a preview session, unless its items place every tile (the dataset then opens at
// once, its headers read by the scheduler's loader, the view's first). A paged catalog (a STAC API
// search) whose first page places its tiles opens that page as the preview while the later pages
// arrive, their footprints shown as they come.
#include "viewer/session_opening.hpp"

#include <algorithm>
#include <chrono>
#include <exception>
#include <utility>

#include "dataset/stac_catalog.hpp"

namespace lidarscout::viewer {

SessionOpening::SessionOpening(std::vector<std::string> paths, SessionOptions options)
    : thread_([this, paths = std::move(paths), options = std::move(options)] { run(paths, options); }) {}

SessionOpening::~SessionOpening() {
    cancel_ = true;
    if (thread_.joinable()) thread_.join();
}

// `placed`: catalog footprints of sources (looked up outside the lock); `sources`: how many there are in all,
// once known; `every_placed`: every source's footprint is noted (the tiles read then add none: a country's
// 152,100 had been drawn again, each frame's new ones, while its dataset opened).
void SessionOpening::note_sources(std::optional<std::size_t> sources,
                                  std::span<const std::optional<dataset::Bounds>> placed, bool every_placed) {
    std::lock_guard lock(mutex_);
    if (sources) progress_.total = *sources;
    for (const auto& b : placed) {
        if (b) footprints_.push_back(*b), progress_.extent.extend(*b);
    }
    every_footprint_noted_ = every_placed;
    sources_noted_ = true;
    sources_known_.notify_all();
}

bool SessionOpening::wait_for_sources(std::chrono::milliseconds timeout) const {
    std::unique_lock lock(mutex_);
    return sources_known_.wait_for(lock, timeout, [&] { return sources_noted_ || finished_.load(); });
}

// A preview session on `ds` (terrain only: the whole dataset's scheduler does the rest), published for the
// window; null when it has no tile or the opening is cancelled.
std::shared_ptr<const Session> SessionOpening::publish_preview(dataset::Dataset ds, const SessionOptions& options) {
    if (ds.tiles.empty() || cancel_) return nullptr;
    auto preview = std::make_shared<Session>();
    preview->dataset = std::make_unique<dataset::Dataset>(std::move(ds));
    SchedulerOptions so = options.scheduler;
    so.cnn = false, so.full_res = false;
    preview->places = std::make_unique<dataset::TileIndex>(*preview->dataset);
    preview->cursor = std::make_unique<CursorReadout>(preview->dataset->frame);
    preview->scheduler = std::make_unique<Scheduler>(*preview->dataset, so);
    std::lock_guard lock(mutex_);
    preview_ = preview;
    return preview;
}

// Opens the pages of a paged catalog read so far (`sources`; more to come) as the preview when their items
// place their tiles: at once, without a request (the preview's scheduler reads their headers and chunk
// points, those in view first, while the later pages are read); it replaces the preview of fewer pages. None
// for an opening that is not the first (SessionOptions::preview_above 0) or a catalog with an overview
// sidecar. Whether it opened.
bool SessionOpening::open_page_preview(std::span<const dataset::TileSource> sources, const SessionOptions& options) {
    if (options.preview_above == 0) return false;
    const auto in_sidecar = [](const dataset::TileSource& s) { return s.item && s.item->overview; };
    if (std::any_of(sources.begin(), sources.end(), in_sidecar)) return false;
    dataset::DatasetOptions d;
    d.crs = options.crs;
    d.placed = true;
    if (!dataset::opens_placed(sources, d)) return false;
    try {
        return publish_preview(dataset::open_sources({{sources.begin(), sources.end()}, {}, {}}, d), options) !=
               nullptr;
    } catch (const Error&) {
        return false;  // (a CRS that cannot be used: the whole opening says why)
    }
}

// Opens the preview (SessionOptions::preview_above) and waits until its chunk points are in, at most
// preview_wait_s: its reads go first, not behind every header of the catalog. Without a preview (a
// small or unplaced catalog, no central tile readable, a cancel) it returns at once; whatever stops
// the preview stops the whole opening too, which reports it.
void SessionOpening::open_preview(std::span<const dataset::TileSource> sources,
                                  std::span<const std::optional<dataset::Bounds>> placed,
                                  const SessionOptions& options) {
    if (options.preview_above == 0 || sources.size() <= options.preview_above || preview()) return;
    const auto in_sidecar = [](const dataset::TileSource& s) { return s.item && s.item->overview; };
    if (std::any_of(sources.begin(), sources.end(), in_sidecar)) return;  // (the sidecar opens them all at once)
    auto central = dataset::central_sources(sources, placed, options.preview_radius_m, options.preview_tiles);
    if (central.empty()) return;
    dataset::DatasetOptions d;
    d.crs = options.crs;
    d.cancel = &cancel_;
    std::shared_ptr<const Session> preview;
    try {
        preview = publish_preview(dataset::open_sources({std::move(central), {}, {}}, d), options);
    } catch (const Error&) {
        return;
    }
    if (!preview) return;
    const auto until = std::chrono::steady_clock::now() + std::chrono::duration<double>(options.preview_wait_s);
    while (!cancel_ && std::chrono::steady_clock::now() < until) {
        const StageProgress loaded = preview->scheduler->stats().tiles_loaded;
        if (loaded.done >= loaded.total) break;
        std::this_thread::sleep_for(std::chrono::milliseconds(10));
    }
}

void SessionOpening::run(const std::vector<std::string>& paths, const SessionOptions& options) {
    dataset::DatasetOptions d;
    d.crs = options.crs;
    d.cancel = &cancel_;
    d.placed = true;  // (the scheduler's loader and residency read headers on demand)
    d.tile_read = [this](const dataset::DatasetTile& t) {
        std::lock_guard lock(mutex_);
        ++progress_.read;
        if (!every_footprint_noted_) footprints_.push_back(t.bounds_m);
        if (t.tile.header.point_count > 0) progress_.extent.extend(t.bounds_m);
    };
    d.progress = [this](std::size_t done, std::size_t total) {
        std::lock_guard lock(mutex_);
        progress_.done = std::max(progress_.done, done);  // callbacks of several threads may cross
        progress_.total = total;
    };
    // A paged catalog's pages so far, opened as the preview at its first page, then again each time they are
    // four times as many, up to SessionOptions::page_preview_most tiles (then only their footprints come).
    std::vector<dataset::TileSource> first_pages;
    std::size_t next_preview = 1;  // the tiles that open the next preview (0: no more)
    std::size_t noted = 0;         // the sources whose footprints were noted as they came
    const auto arriving = [&](std::span<const dataset::TileSource> page, bool more) {
        if (!more) return;  // (a catalog's last document: its footprints come with the rest, their total known)
        note_sources(std::nullopt, dataset::catalog_footprints(page));
        noted += page.size();
        if (cancel_ || next_preview == 0) return;
        first_pages.insert(first_pages.end(), page.begin(), page.end());
        if (first_pages.size() < next_preview) return;
        const bool opened = first_pages.size() <= options.page_preview_most && open_page_preview(first_pages, options);
        next_preview = opened ? 4 * first_pages.size() : 0;
        if (next_preview == 0) first_pages = {};
    };
    try {
        dataset::FoundSources found = dataset::find_tile_sources(paths, arriving);
        if (options.overview_cache) options.overview_cache->use(found.sources);
        first_pages = {};
        const auto placed = dataset::catalog_footprints(found.sources);
        const bool every_placed =
            std::all_of(placed.begin(), placed.end(), [](const auto& b) { return b.has_value(); });
        note_sources(found.sources.size(), std::span(placed).subspan(std::min(noted, placed.size())), every_placed);
        if (!dataset::opens_placed(found.sources, d)) open_preview(found.sources, placed, options);
        Session s;
        s.dataset = std::make_unique<dataset::Dataset>(dataset::open_sources(std::move(found), d));
        dataset::require_tiles(*s.dataset, "view");
        {
            std::lock_guard lock(mutex_);
            progress_.building = true;
        }
        s.cursor = std::make_unique<CursorReadout>(s.dataset->frame);
        s.places = std::make_unique<dataset::TileIndex>(*s.dataset);
        SchedulerOptions scheduler = options.scheduler;
        if ((s.overview_cache = options.overview_cache)) scheduler.loader.on_tile_records = s.overview_cache->keeper();
        if (!cancel_) s.scheduler = std::make_unique<Scheduler>(*s.dataset, scheduler);
        std::lock_guard lock(mutex_);
        session_ = std::move(s);
    } catch (const Error& e) {
        std::lock_guard lock(mutex_);
        error_ = e;
    } catch (const std::exception& e) {  // out of memory, a thread that could not start
        std::lock_guard lock(mutex_);
        error_ = Error(std::string("view: opening failed: ") + e.what());
    }
    std::lock_guard lock(mutex_);
    finished_ = true;
    sources_known_.notify_all();
}

std::shared_ptr<const Session> SessionOpening::preview() const {
    std::lock_guard lock(mutex_);
    return preview_;
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
