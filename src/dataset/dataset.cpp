// open_dataset: expand the paths (folders, tile lists, virtual replica manifests), read every
// tile's metadata on an I/O thread pool (a virtual replica's sources once each, alike records
// shared: dataset/tile.hpp), convert bounds to metres, and summarise what the user should know
// (skipped files, CRS mix).
#include "dataset/dataset.hpp"

#include <algorithm>
#include <array>
#include <atomic>
#include <cmath>
#include <future>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <string_view>
#include <unordered_map>

#include "core/error.hpp"
#include "core/process_memory.hpp"
#include "core/thread_pool.hpp"
#include "dataset/chunk_points.hpp"
#include "dataset/file_search.hpp"
#include "dataset/overview_sidecar.hpp"
#include "dataset/stac_catalog.hpp"
#include "dataset/virtual_replica.hpp"
#include "geo/crs_definition.hpp"
#include "geo/geographic.hpp"
#include "geo/projection.hpp"
#include "io/file.hpp"

namespace lidarscout::dataset {

void Bounds::extend(const Bounds& o) {
    min_x = std::min(min_x, o.min_x);
    min_y = std::min(min_y, o.min_y);
    min_z = std::min(min_z, o.min_z);
    max_x = std::max(max_x, o.max_x);
    max_y = std::max(max_y, o.max_y);
    max_z = std::max(max_z, o.max_z);
}

double Bounds::distance_xy(double x, double y) const {
    const double dx = std::max({min_x - x, 0.0, x - max_x});
    const double dy = std::max({min_y - y, 0.0, y - max_y});
    return std::hypot(dx, dy);
}

void DatasetTile::place(std::span<double> x, std::span<double> y, std::span<double> z) const {
    double xy = xy_to_metres;
    if (to_frame) {
        to_frame->apply(x, y, heights_to_frame ? z : std::span<double>());
        xy = frame_xy_to_metres;
    }
    const double zf = placed_z_to_metres();
    for (double& v : x) v *= xy;
    for (double& v : y) v *= xy;
    for (double& v : z) v *= zf;
}

namespace {

bool usable_factor(double f) { return std::isfinite(f) && f > 0; }

std::string shorten(const std::string& s) { return s.size() > 60 ? s.substr(0, 57) + "..." : s; }

// A short name for the tile's CRS, used to detect datasets that mix CRSs.
std::string crs_key(const las::Crs& crs) {
    if (crs.epsg) return "EPSG:" + std::to_string(*crs.epsg);
    if (!crs.name.empty()) return crs.name;
    return {};
}

}  // namespace

DatasetTile make_dataset_tile(Tile tile, std::uint64_t las_stride) {
    const las::Crs& crs = tile.crs();
    DatasetTile t;  // degrees (no linear unit) stay degrees: the frame is in degrees or reprojects them
    t.xy_to_metres = usable_factor(crs.horizontal_to_metres) && !crs.geographic ? crs.horizontal_to_metres : 1.0;
    const double z = crs.z_to_metres();
    t.z_to_metres = usable_factor(z) ? z : t.xy_to_metres;
    const auto& h = tile.header;
    t.bounds_m.min_x = h.min[0] * t.xy_to_metres;
    t.bounds_m.max_x = h.max[0] * t.xy_to_metres;
    t.bounds_m.min_y = h.min[1] * t.xy_to_metres;
    t.bounds_m.max_y = h.max[1] * t.xy_to_metres;
    t.bounds_m.min_z = h.min[2] * t.z_to_metres;
    t.bounds_m.max_z = h.max[2] * t.z_to_metres;
    if (h.point_count > 0 && t.bounds_m.empty()) {
        throw Error(tile.path(), std::nullopt, "header bounds are not a valid box (min greater than max, or NaN)");
    }
    t.chunk_points = chunk_point_count(tile, las_stride);
    t.points = h.point_count;
    t.tile = std::move(tile);
    return t;
}

namespace {

// Runs `read`; when it throws Error (or runs out of memory), returns nullopt and sets `error` to one
// line naming the file and the cause.
template <typename Read>
auto reading(const std::string& path, std::string& error, Read&& read) -> std::optional<decltype(read())> {
    try {
        return read();
    } catch (const Error& e) {
        error = e.file().empty() ? io::display_path(path) + ": " + e.what() : e.what();
    } catch (const std::bad_alloc&) {
        error = io::display_path(path) + ": out of memory while reading the file";
    }
    return std::nullopt;
}

// The reads of one open_dataset: a plain file's tile as it comes; a virtual replica's source once
// for all the tiles made from it, which then share its TileFile (the first reader thread to ask
// reads it, the others wait for its result); alike records shared between all (SharedRecords).
class TileReads {
public:
    // The tile of `source` (shifted when virtual); on failure, nullopt and `error` set.
    std::optional<Tile> read(const TileSource& source, std::string& error) {
        if (!source.shift) return read_file(source.path, error);
        const Result& shared = source_read(source.path);
        error = shared.error;
        std::optional<Tile> tile = shared.tile;
        if (tile) shift_tile(*tile, *source.shift);
        return tile;
    }
    SharedRecords& records() { return records_; }

private:
    struct Result {
        std::optional<Tile> tile;
        std::string error;
    };

    std::optional<Tile> read_file(const std::string& path, std::string& error) {
        TileOptions options;
        options.shared_records = &records_;
        return reading(path, error, [&] { return read_tile(io::File::open(path), options); });
    }

    const Result& source_read(const std::string& path) {
        std::promise<Result> promise;
        std::shared_future<Result> result;
        bool first = false;
        {
            std::lock_guard lock(mutex_);
            auto [it, inserted] = sources_.try_emplace(path);
            if (inserted) it->second = promise.get_future().share(), first = true;
            result = it->second;
        }
        if (first) {
            Result r;
            r.tile = read_file(path, r.error);
            promise.set_value(std::move(r));
        }
        return result.get();  // the value lives in the shared state, which sources_ keeps
    }

    SharedRecords records_;
    std::mutex mutex_;
    std::map<std::string, std::shared_future<Result>> sources_;
};

// The tile of `source`, read.
std::optional<DatasetTile> read_one(const TileSource& source, std::uint64_t las_stride, TileReads& reads,
                                    std::string& error) {
    std::optional<Tile> tile = reads.read(source, error);
    if (!tile) return std::nullopt;
    return reading(source.path, error, [&] { return make_dataset_tile(std::move(*tile), las_stride); });
}

// One warning per compound CRS used by its horizontal part alone (geo::fall_back_to_horizontal),
// naming its first tile and how many tiles use it.
void add_fallback_warnings(Dataset& ds) {
    std::map<std::string, std::pair<std::string, std::size_t>> by_message;  // message -> first tile, tiles
    for (const auto& t : ds.tiles) {
        const std::string message = geo::vertical_fallback_message(t.tile.crs());
        if (message.empty()) continue;
        auto& [first, n] = by_message[message];
        if (n++ == 0) first = t.tile.path();
    }
    for (const auto& [message, seen] : by_message) {
        const std::string more = seen.second > 1 ? " (and " + std::to_string(seen.second - 1) + " more tiles)" : "";
        ds.warnings.add({DiagnosticLevel::warning, seen.first, std::nullopt,
                         io::display_path(seen.first) + more + ": " + message});
    }
}

void add_crs_warnings(Dataset& ds) {
    add_fallback_warnings(ds);
    std::map<std::string, std::size_t> by_crs;
    std::size_t without_unit = 0;
    for (const auto& t : ds.tiles) {
        ++by_crs[crs_key(t.tile.crs())];
        if (!t.tile.crs().geographic && !usable_factor(t.tile.crs().horizontal_to_metres)) ++without_unit;
    }
    if (without_unit > 0) {
        ds.warnings.warn(std::to_string(without_unit) + " of " + std::to_string(ds.tiles.size()) +
                              " tiles give no linear unit; their coordinates are taken as metres");
    }
    std::erase_if(by_crs, [](const auto& kv) { return kv.first.empty(); });
    if (by_crs.size() > 1) {
        std::string list;
        for (const auto& [name, n] : by_crs) {
            list += (list.empty() ? "" : ", ") + name + " (" + std::to_string(n) + " tiles)";
        }
        ds.warnings.warn("tiles use different coordinate reference systems: " + list +
                              "; they are reprojected to " + shorten(ds.frame.crs));
    }
}

// Header reads are I/O bound (many small reads per file when the cache is cold), so they
// run on more threads than cores; the pool is kept between calls because starting dozens
// of threads costs more than reading a hundred warm headers.
// One pool per size asked for, never destroyed (another thread may be using it).
ThreadPool& header_pool(unsigned threads) {
    static std::mutex mutex;
    static std::map<unsigned, std::unique_ptr<ThreadPool>> pools;
    std::lock_guard lock(mutex);
    auto& pool = pools[threads];
    if (!pool) pool = std::make_unique<ThreadPool>(threads);
    return *pool;
}

// Where to reproject data in degrees: the UTM zone at the centre of the tiles in degrees (their
// bounds are longitude/latitude), else of the first tile PROJ can place in longitude/latitude.
std::string utm_hint(const Dataset& ds) {
    Bounds lonlat;
    for (const auto& t : ds.tiles) {
        if (t.tile.crs().geographic && t.tile.header.point_count > 0) lonlat.extend(t.bounds_m);
    }
    for (std::size_t i = 0; lonlat.empty() && i < ds.tiles.size(); ++i) {
        const auto& h = ds.tiles[i].tile.header;
        try {
            const auto b = geo::lonlat_bounds(geo::crs_definition(ds.tiles[i].tile.crs()), h.min[0], h.min[1],
                                              h.max[0], h.max[1]);
            lonlat.min_x = b.west, lonlat.min_y = b.south, lonlat.max_x = b.east, lonlat.max_y = b.north;
        } catch (const Error&) {
            // no CRS, or one PROJ cannot place: the next tile
        }
    }
    if (lonlat.empty()) return "--crs with a projected CRS (the UTM zone of the data)";
    const geo::UtmZone zone = geo::utm_zone_at(lonlat.centre_x(), lonlat.centre_y());
    return "--crs " + zone.crs + " (" + zone.name + ", at the data's centre)";
}

// Whether a tile in the CRS `def` is in the frame's CRS: the same definition, or the horizontal EPSG
// CRS the frame names alone (its heights then stay as stored, as a reprojection would leave them).
bool in_frame_crs(const std::string& def, const Frame& frame) {
    if (def == frame.crs) return true;
    const geo::EpsgCodes tile = geo::epsg_codes_of_definition(def), wanted = geo::epsg_codes_of_definition(frame.crs);
    return tile.horizontal && tile.horizontal == wanted.horizontal && !wanted.vertical;
}

// The frame: the CRS asked for, else the one most tiles use (the first such tile's); a CRS in degrees
// only when the caller accepts degrees.
// The frame of the CRS asked for (options.crs); `hint` names the --crs to give instead of one in degrees.
Frame asked_frame(const DatasetOptions& options, const std::function<std::string()>& hint) {
    const geo::CrsInfo info = geo::crs_info(options.crs);
    if (info.geographic && !options.accept_degrees) {
        throw Error::in_stage("dataset", "the CRS " + shorten(options.crs) + " is in degrees (longitude, "
                              "latitude); a projected CRS in metres or feet is needed here: give " + hint());
    }
    return {options.crs, info.geographic ? 1.0 : info.xy_to_metres,
            usable_factor(info.z_to_metres) ? info.z_to_metres : 1.0, info.geographic};
}

void choose_frame(Dataset& ds, const DatasetOptions& options) {
    if (!options.crs.empty()) {
        ds.frame = asked_frame(options, [&] { return utm_hint(ds); });
        return;
    }
    const auto votes = [&](const DatasetTile& t) { return options.accept_degrees || !t.tile.crs().geographic; };
    std::map<std::string, std::size_t> count;
    std::string best;
    std::size_t best_count = 0;
    for (const auto& t : ds.tiles) {
        const std::string key = crs_key(t.tile.crs());
        if (key.empty() || !votes(t)) continue;
        if (++count[key] > best_count) best_count = count[key], best = key;
    }
    for (const auto& t : ds.tiles) {
        if (!best.empty() && votes(t) && crs_key(t.tile.crs()) == best) {
            ds.frame = {geo::crs_definition(t.tile.crs()), t.xy_to_metres, t.z_to_metres, t.tile.crs().geographic};
            return;
        }
    }
}

// One warning per source CRS when PROJ has only a ballpark operation to the frame at the
// first tile's centre: positions or heights are then not shifted between datums.
void warn_if_ballpark(const DatasetTile& t, const geo::CrsTransform& transform, Diagnostics& warnings) {
    const auto& h = t.tile.header;
    const std::string op = transform.ballpark_at(0.5 * (h.min[0] + h.max[0]), 0.5 * (h.min[1] + h.max[1]),
                                                 0.5 * (h.min[2] + h.max[2]));
    if (op.empty()) return;
    warnings.add({DiagnosticLevel::warning, t.tile.path(), std::nullopt,
                  "PROJ has only a ballpark transformation from " + shorten(transform.source()) + " to " +
                      shorten(transform.target()) + " (" + op + "): the step PROJ calls ballpark applies no datum " +
                      "shift, so the result can be metres off; a datum grid is probably not installed"});
}

// Points the tile at the frame when its CRS differs (transforms shared per source CRS) and
// moves its bounds there. Throws Error when PROJ cannot.
using TransformCache = std::map<std::string, std::shared_ptr<const geo::CrsTransform>>;
void reproject(DatasetTile& t, const Frame& frame, TransformCache& cache, Diagnostics& warnings) {
    const std::string def = geo::crs_definition(t.tile.crs());
    if (def.empty() || frame.crs.empty() || in_frame_crs(def, frame)) return;
    auto& transform = cache[def];
    if (!transform) {
        transform = std::make_shared<const geo::CrsTransform>(def, frame.crs);
        warn_if_ballpark(t, *transform, warnings);
    }
    t.to_frame = transform;
    t.frame_xy_to_metres = frame.xy_to_metres;
    t.heights_to_frame = transform->transforms_heights();
    t.frame_z_to_metres = frame.z_to_metres;
    const auto& h = t.tile.header;
    double x0 = h.min[0], y0 = h.min[1], x1 = h.max[0], y1 = h.max[1];
    transform->apply_bounds(x0, y0, x1, y1);
    t.bounds_m.min_x = x0 * frame.xy_to_metres;
    t.bounds_m.min_y = y0 * frame.xy_to_metres;
    t.bounds_m.max_x = x1 * frame.xy_to_metres;
    t.bounds_m.max_y = y1 * frame.xy_to_metres;
    if (t.heights_to_frame) {  // the height range moved as at the tile's centre
        double cx = 0.5 * (h.min[0] + h.max[0]), cy = 0.5 * (h.min[1] + h.max[1]);
        double lx = cx, ly = cy, low = h.min[2], high = h.max[2];
        transform->apply(lx, ly, low);
        transform->apply(cx, cy, high);
        t.bounds_m.min_z = low * frame.z_to_metres;
        t.bounds_m.max_z = high * frame.z_to_metres;
    }
}

// Reprojects the tiles not in the frame's CRS; a tile PROJ cannot place is skipped, and so is a tile
// in degrees left in degrees in a frame that is not (naming the --crs that would place it).
void place_tiles(Dataset& ds, const DatasetOptions& options) {
    choose_frame(ds, options);
    TransformCache cache;
    const bool degrees = std::any_of(ds.tiles.begin(), ds.tiles.end(), [](const DatasetTile& t) {
        return t.tile.crs().geographic;
    });
    const std::string hint = degrees && !ds.frame.geographic ? utm_hint(ds) : "";
    std::size_t kept = 0;  // the tiles kept move down in place (no second vector of 100,000s)
    for (auto& t : ds.tiles) {
        try {
            reproject(t, ds.frame, cache, ds.warnings);
            if (t.tile.crs().geographic && !t.to_frame && !ds.frame.geographic) {
                throw Error("coordinates are in degrees (longitude, latitude); give " + hint + " to work in metres");
            }
            if (&t != &ds.tiles[kept]) ds.tiles[kept] = std::move(t);
            ++kept;
        } catch (const Error& e) {
            ds.skipped.push_back({t.tile.path(), t.tile.path() + ": " + e.what()});
        }
    }
    ds.tiles.erase(ds.tiles.begin() + static_cast<std::ptrdiff_t>(kept), ds.tiles.end());
}

// Where an overview sidecar places tiles (overview_tiles): into the dataset's tiles, by source.
struct SidecarPlacing {
    std::span<DatasetTile> tiles;
    std::uint64_t las_stride;
    SharedRecords& records;
};

// Places the sources `members` of the sidecar at `path` from it (by their items' ids) into `into`; one
// warning when the sidecar cannot be used (its tiles are then read), one for the items it does not hold (or whose
// entry does not make a tile: read themselves too).
void place_from_sidecar(const std::string& path, const std::vector<std::size_t>& members,
                        std::span<const TileSource> sources, SidecarPlacing& into, Diagnostics& warnings,
                        ThreadPool& pool) {
    OverviewSidecar sidecar;
    try {
        sidecar = read_overview_sidecar(path);
    } catch (const Error& e) {
        const std::string why = e.file().empty() ? io::display_path(path) + ": " + e.what() : e.what();
        return warnings.warn("overview sidecar not used (" + why + "): its catalog's tiles are read themselves");
    }
    constexpr std::size_t kRepeated = static_cast<std::size_t>(-1);
    std::unordered_map<std::string_view, std::size_t> by_id;
    for (std::size_t k = 0; k < sidecar.entries.size(); ++k) {
        const auto [it, added] = by_id.try_emplace(sidecar.entries[k].id, k);
        if (!added) it->second = kRepeated;
    }
    std::atomic<std::size_t> missing{0};
    pool.for_each(members.size(), [&](std::size_t k) {
        const TileSource& s = sources[members[k]];
        const auto it = by_id.find(s.item->id);
        try {
            if (it == by_id.end() || it->second == kRepeated) throw Error("not in the sidecar");
            const std::size_t i = members[k];
            into.tiles[i] = make_dataset_tile(tile_from_overview(sidecar, it->second, s.path, &into.records),
                                              into.las_stride);
        } catch (const Error&) {
            ++missing;
        }
    });
    if (missing > 0) {
        warnings.warn(std::to_string(missing.load()) + " of " + std::to_string(members.size()) + " tiles of the "
                      "catalog are not in its overview sidecar " + io::display_path(path) + ": read themselves");
    }
}

// Whether an open with `options` reads the overview sidecar `source`'s catalog names (DatasetOptions::use_overview
// and --no-overview's use_overview_sidecars).
bool reads_sidecar(const TileSource& source, const DatasetOptions& options) {
    return source.item && source.item->overview && !source.shift && options.use_overview && overview_sidecars_in_use();
}

// The tiles their catalogs' overview sidecars place, written into `tiles` (by source: a tile placed has its file,
// one not placed none; a tile placed so, 600 bytes, had been made aside and moved: a country's 152,100 are 90 MB of
// fresh pages).
void overview_tiles(std::span<const TileSource> sources, const DatasetOptions& options, std::span<DatasetTile> tiles,
                    SharedRecords& records, Diagnostics& warnings, ThreadPool& pool) {
    std::map<std::string, std::vector<std::size_t>> by_sidecar;
    for (std::size_t i = 0; i < sources.size(); ++i) {
        if (reads_sidecar(sources[i], options)) by_sidecar[*sources[i].item->overview].push_back(i);
    }
    SidecarPlacing into{tiles, options.las_stride, records};
    for (const auto& [path, members] : by_sidecar) place_from_sidecar(path, members, sources, into, warnings, pool);
}

// The dataset's bounds and counts, from its tiles'.
void add_up(Dataset& ds) {
    ds.bounds_m = {};
    ds.point_count = ds.chunk_point_count = 0;
    for (const auto& t : ds.tiles) {
        if (t.points > 0) ds.bounds_m.extend(t.bounds_m);
        ds.point_count += t.points;
        ds.chunk_point_count += t.chunk_points;
    }
}

void summarise(Dataset& ds) {
    add_up(ds);
    add_crs_warnings(ds);
}

}  // namespace

// The tiles of a dataset placed by its catalog: their sources, and per tile whether its header is read
// (an atomic state: a reader publishes the tile it wrote with a release store, a user looks with an
// acquire load), why a read failed, and what settle_tiles takes from each header read.
class PlacedTiles {
public:
    PlacedTiles(std::vector<TileSource> sources, std::uint64_t las_stride, bool frame_asked)
        : sources_(std::move(sources)), state_(std::make_unique<std::atomic<std::uint8_t>[]>(sources_.size())),
          read_bounds_(std::make_unique<Bounds[]>(sources_.size())), las_stride_(las_stride),
          frame_asked_(frame_asked) {}

    bool frame_asked() const { return frame_asked_; }

    bool is_ready(std::size_t i) const { return state_[i].load(std::memory_order_acquire) == kReady; }
    bool tried(std::size_t i) const { return state_[i].load(std::memory_order_acquire) >= kReady; }
    std::size_t ready_count() const { return ready_count_.load(); }
    const std::string& path(std::size_t i) const { return sources_[i].path; }
    // Tile i's header's bounds (once is_ready: written before the release store that publishes the tile).
    const Bounds& read_bounds(std::size_t i) const { return read_bounds_[i]; }

    Diagnostics corrections(std::size_t from) const {
        std::lock_guard lock(mutex_);
        Diagnostics out;
        for (std::size_t k = from; k < corrections_.size(); ++k) out.add(corrections_[k]);
        return out;
    }
    std::size_t corrections_count() const {
        std::lock_guard lock(mutex_);
        return corrections_.size();
    }

    std::string error(std::size_t i) const {
        std::lock_guard lock(mutex_);
        const auto it = errors_.find(i);
        return it == errors_.end() ? std::string() : it->second;
    }

    // Reads tile i into `ds` once; the callers that come while it is read wait for it.
    bool ready(Dataset& ds, std::size_t i) {
        std::uint8_t s = state_[i].load(std::memory_order_acquire);
        while (s < kReady) {
            if (s == kUnread) {
                if (!state_[i].compare_exchange_weak(s, kReading, std::memory_order_acquire)) continue;
                const bool ok = read(ds, i);
                ready_count_ += ok;
                state_[i].store(ok ? kReady : kFailed, std::memory_order_release);
                state_[i].notify_all();
                return ok;
            }
            state_[i].wait(kReading, std::memory_order_acquire);
            s = state_[i].load(std::memory_order_acquire);
        }
        return s == kReady;
    }

    // settle_tiles (the caller holds `ds` alone); `drop_unread`: the tiles not read leave too.
    void settle(Dataset& ds, bool drop_unread) {
        std::lock_guard lock(mutex_);
        std::size_t kept = 0;
        for (std::size_t i = 0; i < ds.tiles.size(); ++i) {
            const std::uint8_t s = state_[i].load();
            if (s == kFailed) {
                ds.skipped.push_back({io::display_path(sources_[i].path), errors_[i]});
                continue;
            }
            if (s == kUnread && drop_unread) continue;
            if (s == kReady) correct(ds.tiles[i], i, ds.warnings);
            if (kept != i) {
                ds.tiles[kept] = std::move(ds.tiles[i]);
                sources_[kept] = std::move(sources_[i]);
                read_bounds_[kept] = read_bounds_[i];
                state_[kept].store(s);
            }
            ++kept;
        }
        ds.tiles.erase(ds.tiles.begin() + static_cast<std::ptrdiff_t>(kept), ds.tiles.end());
        sources_.resize(kept);
        errors_.clear(), headers_.clear(), corrections_.clear();
        ds.warnings.append(warnings_);
        warnings_ = {};
    }

private:
    enum : std::uint8_t { kUnread, kReading, kReady, kFailed };

    // What a tile's header says where its item spoke first (kept for settle_tiles).
    struct Header {
        Bounds bounds_m;
        std::uint64_t points = 0, chunk_points = 0;
        std::string disagreement;  // with its item ("" when none)
    };

    bool read(Dataset& ds, std::size_t i) {
        const TileSource& source = sources_[i];
        std::string error;
        std::optional<DatasetTile> tile = read_one(source, las_stride_, reads_, error);
        if (tile) {
            try {
                to_frame(*tile, ds.frame);
            } catch (const Error& e) {
                error = io::display_path(source.path) + ": " + e.what();
                tile.reset();
            }
        }
        if (!tile) {
            std::lock_guard lock(mutex_);
            errors_[i] = error + " (" + item_name(*source.item) + ")";
            return false;
        }
        Header header{tile->bounds_m, tile->points, tile->chunk_points, item_disagreement(*source.item, tile->tile)};
        read_bounds_[i] = tile->bounds_m;
        {
            std::lock_guard lock(mutex_);
            if (!header.disagreement.empty()) {
                corrections_.push_back({DiagnosticLevel::warning, io::display_path(source.path), std::nullopt,
                                        header.disagreement});
            }
            headers_[i] = std::move(header);
        }
        DatasetTile& t = ds.tiles[i];  // its placed fields stay: other threads read them
        t.tile = std::move(tile->tile);
        t.xy_to_metres = tile->xy_to_metres, t.z_to_metres = tile->z_to_metres;
        t.to_frame = std::move(tile->to_frame);
        t.frame_xy_to_metres = tile->frame_xy_to_metres, t.frame_z_to_metres = tile->frame_z_to_metres;
        t.heights_to_frame = tile->heights_to_frame;
        return true;
    }

    // Reprojects a tile read into the frame as place_tiles does; throws Error when it cannot be placed.
    void to_frame(DatasetTile& t, const Frame& frame) {
        std::lock_guard lock(mutex_);
        reproject(t, frame, transforms_, warnings_);
        if (t.tile.crs().geographic && !t.to_frame && !frame.geographic) {
            throw Error("coordinates are in degrees (longitude, latitude); give --crs with a projected CRS (the "
                        "UTM zone of the data) to work in metres");
        }
    }

    // A tile read takes its header's bounds and counts, and names its item's disagreement.
    void correct(DatasetTile& t, std::size_t i, Diagnostics& warnings) {
        const auto it = headers_.find(i);
        if (it == headers_.end()) return;
        const Header& h = it->second;
        t.bounds_m = h.bounds_m, t.points = h.points, t.chunk_points = h.chunk_points;
        if (!h.disagreement.empty()) {
            warnings.add({DiagnosticLevel::warning, io::display_path(sources_[i].path), std::nullopt, h.disagreement});
        }
    }

    std::vector<TileSource> sources_;  // by tile
    std::unique_ptr<std::atomic<std::uint8_t>[]> state_;
    std::unique_ptr<Bounds[]> read_bounds_;  // by tile: its header's, once read
    std::atomic<std::size_t> ready_count_{0};
    const std::uint64_t las_stride_;
    const bool frame_asked_;  // the frame is the CRS the caller asked for (not the items')
    TileReads reads_;
    mutable std::mutex mutex_;  // guards what follows
    std::unordered_map<std::size_t, std::string> errors_;
    std::unordered_map<std::size_t, Header> headers_;
    TransformCache transforms_;
    Diagnostics warnings_;  // of reprojections
    std::vector<Diagnostic> corrections_;  // the tiles read whose headers disagree with their items, in order
};

bool Dataset::is_ready(std::size_t i) const { return !placed || placed->is_ready(i); }

bool Dataset::ready(std::size_t i) const {
    // The tiles live in the vector's storage (never const objects, whatever the Dataset's constness): the
    // tile written is one no other thread uses until the release store that publishes it.
    return !placed || placed->ready(const_cast<Dataset&>(*this), i);
}

std::string Dataset::ready_error(std::size_t i) const { return placed ? placed->error(i) : std::string(); }

const std::string& Dataset::path(std::size_t i) const { return placed ? placed->path(i) : tiles[i].tile.path(); }

std::size_t Dataset::tiles_ready() const { return placed ? placed->ready_count() : tiles.size(); }

const Bounds& Dataset::bounds(std::size_t i) const {
    return placed && placed->is_ready(i) ? placed->read_bounds(i) : tiles[i].bounds_m;
}

Diagnostics Dataset::corrections(std::size_t from) const { return placed ? placed->corrections(from) : Diagnostics(); }

std::size_t Dataset::corrections_count() const { return placed ? placed->corrections_count() : 0; }

void ensure_tiles(const Dataset& ds, std::span<const std::uint32_t> indices, unsigned io_threads) {
    if (!ds.placed) return;
    std::vector<std::uint32_t> todo;
    std::vector<std::string> paths;
    for (const std::uint32_t i : indices) {
        if (ds.placed->tried(i)) continue;
        todo.push_back(i);
        paths.push_back(ds.placed->path(i));
    }
    if (todo.empty()) return;
    io::File::prefetch(paths);  // remote tiles: their header requests in flight at once
    header_pool(std::max(1u, io_threads)).for_each(todo.size(), [&](std::size_t k) { ds.ready(todo[k]); });
}

void ensure_all_tiles(const Dataset& ds, unsigned io_threads) {
    std::vector<std::uint32_t> all(ds.tiles.size());
    for (std::uint32_t i = 0; i < all.size(); ++i) all[i] = i;
    ensure_tiles(ds, all, io_threads);
}

namespace {

void settle(Dataset& ds, bool drop_unread) {
    if (!ds.placed) return;
    ds.placed->settle(ds, drop_unread);
    add_up(ds);
    if (ds.placed->ready_count() < ds.tiles.size()) return;
    // Every tile read: a dataset like one opened by reading them, its frame too where the items chose it
    // (the units the tiles' records say, not PROJ's for the items' CRS: they may differ in the last bit).
    if (!ds.placed->frame_asked()) {
        DatasetOptions options;
        options.accept_degrees = ds.frame.geographic;
        choose_frame(ds, options);
    }
    ds.placed.reset();
    add_crs_warnings(ds);
}

}  // namespace

void settle_tiles(Dataset& ds) { settle(ds, false); }

void keep_tiles_touching(Dataset& ds, const std::function<bool(const Bounds&)>& touches, unsigned io_threads) {
    if (!ds.placed) return;
    const double f = ds.frame.xy_to_metres;
    std::vector<std::uint32_t> wanted;
    for (std::uint32_t i = 0; i < ds.tiles.size(); ++i) {
        Bounds b = ds.tiles[i].bounds_m;
        b.min_x /= f, b.min_y /= f, b.max_x /= f, b.max_y /= f;
        if (!b.empty() && touches(b)) wanted.push_back(i);
    }
    ensure_tiles(ds, wanted, io_threads);
    settle(ds, true);
}

namespace {

// The frame of a catalog's items: the CRS asked for, else the one most items give.
Frame items_frame(std::span<const TileSource> sources, const DatasetOptions& options) {
    if (!options.crs.empty()) return asked_frame(options, [] { return std::string("a projected CRS"); });
    std::map<std::string_view, std::size_t> count;
    std::string_view best;
    std::size_t best_count = 0;
    for (const auto& s : sources) {
        if (++count[s.item->crs.str()] > best_count) best_count = count[s.item->crs.str()], best = s.item->crs.str();
    }
    const geo::CrsInfo info = geo::crs_info(std::string(best));
    return {std::string(best), info.xy_to_metres, usable_factor(info.z_to_metres) ? info.z_to_metres : 1.0, false};
}

// The frame of a dataset the items of `sources` place (DatasetOptions::placed), with the tiles' footprints;
// nullopt when an item does not place its tile: no pc:count, bbox or CRS PROJ knows, a CRS other than the
// frame's, an overview sidecar that is read (it places them itself).
std::optional<std::pair<Frame, std::vector<Bounds>>> placing(std::span<const TileSource> sources,
                                                              const DatasetOptions& options) {
    if (!options.placed || sources.empty()) return std::nullopt;
    std::vector<Bounds> footprints;
    footprints.reserve(sources.size());
    for (const auto& s : sources) {
        if (!s.item || s.shift || !s.item->count || s.item->crs.empty() || reads_sidecar(s, options)) {
            return std::nullopt;
        }
        auto b = catalog_footprint(*s.item);
        if (!b || b->empty()) return std::nullopt;  // (an inverted box places nothing)
        footprints.push_back(*b);
    }
    Frame frame = items_frame(sources, options);
    for (const auto& s : sources) {
        if (!in_frame_crs(s.item->crs.str(), frame)) return std::nullopt;
    }
    return std::pair{std::move(frame), std::move(footprints)};
}

// The dataset placed by the items of `found`, or nullopt (placing).
std::optional<Dataset> open_placed(FoundSources& found, const DatasetOptions& options) {
    const auto& sources = found.sources;
    auto place = placing(sources, options);
    if (!place) return std::nullopt;
    const auto& footprints = place->second;
    Dataset ds;
    ds.frame = std::move(place->first);
    ds.las_stride = options.las_stride;
    ds.skipped = std::move(found.errors);
    ds.warnings = std::move(found.warnings);
    ds.tiles.resize(sources.size());
    const std::uint64_t stride = std::max<std::uint64_t>(options.las_stride, 1);
    for (std::size_t i = 0; i < sources.size(); ++i) {
        DatasetTile& t = ds.tiles[i];
        t.bounds_m = footprints[i];
        t.points = *sources[i].item->count;
        t.chunk_points = (t.points + stride - 1) / stride;
        t.xy_to_metres = ds.frame.xy_to_metres, t.z_to_metres = ds.frame.z_to_metres;
    }
    ds.placed = std::make_shared<PlacedTiles>(std::move(found.sources), options.las_stride, !options.crs.empty());
    add_up(ds);
    if (options.progress) options.progress(ds.tiles.size(), ds.tiles.size());
    return ds;
}

}  // namespace

namespace {
std::atomic<bool> overview_sidecars_used{true};
}  // namespace

void use_overview_sidecars(bool used) { overview_sidecars_used = used; }
bool overview_sidecars_in_use() { return overview_sidecars_used; }

void require_tiles(const Dataset& ds, const std::string& stage) {
    if (!ds.tiles.empty()) return;
    std::string why;
    for (std::size_t i = 0; i < ds.skipped.size() && i < 3; ++i) why += (i ? "; " : ": ") + ds.skipped[i].error;
    if (ds.skipped.size() > 3) why += "; and " + std::to_string(ds.skipped.size() - 3) + " more";
    throw Error::in_stage(stage, "no readable LAS/LAZ tile in the given paths" + why);
}

std::optional<Bounds> catalog_footprint(const CatalogItem& item) {
    if (!item.bbox) return std::nullopt;
    // Units per CRS text, looked up once (a catalog's items mostly share one CRS).
    static std::mutex mutex;
    static std::map<std::string, std::optional<std::pair<double, double>>> units;
    std::optional<std::pair<double, double>> unit{{1.0, 1.0}};
    if (!item.crs.empty()) {
        std::lock_guard lock(mutex);
        const auto [it, added] = units.try_emplace(item.crs.str());
        if (added) {
            try {
                const geo::CrsInfo info = geo::crs_info(item.crs);
                if (!info.geographic) it->second = std::pair{info.xy_to_metres, info.z_to_metres};
            } catch (const Error&) {
                // unknown to PROJ: no footprint before the header
            }
        }
        unit = it->second;
    }
    if (!unit) return std::nullopt;
    const auto [xy, z] = *unit;
    const auto& b = *item.bbox;
    Bounds out;
    out.min_x = b[0] * xy, out.min_y = b[1] * xy, out.max_x = b[3] * xy, out.max_y = b[4] * xy;
    out.min_z = std::isnan(b[2]) ? 0.0 : b[2] * z;
    out.max_z = std::isnan(b[5]) ? 0.0 : b[5] * z;
    return out;
}

std::pair<double, double> patch_grid_origin(const Dataset& ds, double patch) {
    if (ds.bounds_m.empty()) return {0.0, 0.0};
    return {std::floor(ds.bounds_m.min_x / patch) * patch, std::floor(ds.bounds_m.min_y / patch) * patch};
}

bool opens_placed(std::span<const TileSource> sources, const DatasetOptions& options) {
    try {
        return placing(sources, options).has_value();
    } catch (const Error&) {
        return false;  // (a CRS asked for that cannot be used: open_sources says why)
    }
}

Dataset open_dataset(const std::vector<std::string>& paths, const DatasetOptions& options) {
    return open_sources(find_tile_sources(paths), options);
}

std::vector<std::optional<Bounds>> catalog_footprints(std::span<const TileSource> sources) {
    std::vector<std::optional<Bounds>> out;
    out.reserve(sources.size());
    for (const auto& s : sources) out.push_back(s.item ? catalog_footprint(*s.item) : std::nullopt);
    return out;
}

std::vector<TileSource> central_sources(std::span<const TileSource> sources,
                                        std::span<const std::optional<Bounds>> footprints, double radius_m,
                                        std::size_t most) {
    Bounds extent;
    for (const auto& b : footprints) {
        if (!b) return {};
        extent.extend(*b);
    }
    if (extent.empty()) return {};
    std::vector<std::pair<double, std::size_t>> near;  // (distance to the centre, source)
    for (std::size_t i = 0; i < sources.size(); ++i) {
        const double d = footprints[i]->distance_xy(extent.centre_x(), extent.centre_y());
        if (d <= radius_m) near.emplace_back(d, i);
    }
    std::sort(near.begin(), near.end());
    near.resize(std::min(near.size(), most));
    std::vector<TileSource> out;
    for (const auto& [d, i] : near) out.push_back(sources[i]);
    return out;
}

Dataset open_sources(FoundSources found, const DatasetOptions& options) {
    if (options.sources_found) options.sources_found(found.sources);
    if (auto placed = open_placed(found, options)) return std::move(*placed);
    Dataset ds;
    ds.las_stride = options.las_stride;
    ds.skipped = std::move(found.errors);
    ds.warnings = std::move(found.warnings);
    const std::vector<TileSource>& sources = found.sources;
    const std::size_t n = sources.size();
    std::vector<DatasetTile> tiles(n);  // a tile not read has no file
    std::vector<std::string> errors(n), disagreements(n);
    std::atomic<std::size_t> done{0};
    ThreadPool& pool = header_pool(std::max(1u, options.io_threads));
    TileReads reads;
    const bool sidecar_read = std::any_of(sources.begin(), sources.end(),
                                          [&](const TileSource& s) { return reads_sidecar(s, options); });
    overview_tiles(sources, options, tiles, reads.records(), ds.warnings, pool);
    forget_overview_prefetch();  // (one a catalog named, where this open did not take it)
    const auto placed = [&](std::size_t i) { return tiles[i].tile.file != nullptr; };  // (before its own read)
    const bool any_placed = std::any_of(tiles.begin(), tiles.end(), [](const DatasetTile& t) { return t.tile.file; });
    if (sidecar_read && !any_placed) {
        // A sidecar that placed nothing (unreadable, damaged, missing: its warning said so): the items place the
        // tiles as any catalog's do, where they can, rather than every header being read first.
        DatasetOptions items_alone = options;
        items_alone.use_overview = false;
        if (auto by_items = open_placed(found, items_alone)) {
            by_items->skipped = std::move(ds.skipped);
            by_items->warnings = std::move(ds.warnings);
            return std::move(*by_items);
        }
    }
    std::vector<std::string> source_paths;
    for (std::size_t i = 0; i < n; ++i) {
        if (!placed(i)) source_paths.push_back(sources[i].path);
    }
    io::File::prefetch(source_paths);  // remote tiles: every header request in flight at once
    source_paths = {};
    const auto cancelled = [&] { return options.cancel && options.cancel->load(); };
    pool.for_each(n, [&](std::size_t i) {
        if (cancelled()) return;
        if (!placed(i)) {
            if (auto tile = read_one(sources[i], options.las_stride, reads, errors[i])) tiles[i] = std::move(*tile);
        }
        if (tiles[i].tile.file) {
            if (sources[i].item) disagreements[i] = item_disagreement(*sources[i].item, tiles[i].tile);
            if (options.tile_read) options.tile_read(tiles[i]);
        }
        const std::size_t d = done.fetch_add(1) + 1;
        if (options.progress) options.progress(d, n);
    });
    if (cancelled()) throw Error::in_stage("dataset", "opening cancelled");
    for (std::size_t i = 0; i < n; ++i) {
        if (!tiles[i].tile.file) {  // a catalog's tile names its item (and the item its catalog)
            const std::string item = sources[i].item ? " (" + item_name(*sources[i].item) + ")" : "";
            ds.skipped.push_back({io::display_path(sources[i].path), errors[i] + item});
        }
        if (!disagreements[i].empty()) {
            ds.warnings.add({DiagnosticLevel::warning, io::display_path(sources[i].path), std::nullopt,
                             disagreements[i]});
        }
    }
    std::erase_if(tiles, [](const DatasetTile& t) { return !t.tile.file; });
    ds.tiles = std::move(tiles);
    place_tiles(ds, options);
    summarise(ds);
    found = {};
    trim_heap();  // what the manifest's parse and the reads freed goes back to the system
    return ds;
}

}  // namespace lidarscout::dataset
