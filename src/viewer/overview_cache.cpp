// The viewer's overview cache: the cached sidecar named to the sources, the chunk-point records kept
// as the loader reads them, the write on its own thread once all are in, and the least recently used
// sidecars dropped past the bound.
#include "viewer/overview_cache.hpp"

#include <algorithm>
#include <system_error>
#include <utility>

#include "core/error.hpp"
#include "core/sha256.hpp"
#include "dataset/chunk_points.hpp"
#include "dataset/overview_sidecar.hpp"
#include "dataset/overview_writer.hpp"
#include "dataset/stac_catalog.hpp"
#include "io/file.hpp"

namespace lidarscout::viewer {
namespace fs = std::filesystem;

namespace {

constexpr const char* kSuffix = ".overview.laz";

// The key of what was opened: the SHA-256 of the paths as shown (no credentials), one a line.
std::string key_of(const std::vector<std::string>& paths) {
    std::string text;
    for (const auto& p : paths) text += io::display_path(p) + "\n";
    return sha256_hex({reinterpret_cast<const std::uint8_t*>(text.data()), text.size()});
}

// The records the dataset's tile `i` has for the sidecar: those the loader kept, else its sidecar's.
std::vector<std::uint8_t> records_of(const dataset::Dataset& ds, std::size_t i,
                                     std::map<std::uint32_t, std::vector<std::uint8_t>>& kept) {
    if (const auto it = kept.find(static_cast<std::uint32_t>(i)); it != kept.end()) return std::move(it->second);
    const auto& t = ds.tiles[i].tile;
    const auto held = dataset::overview_records(t, dataset::chunk_point_count(t, ds.las_stride));
    return {held.begin(), held.end()};
}

}  // namespace

OverviewCache::OverviewCache(const std::vector<std::string>& paths, OverviewCacheSettings settings)
    : folder_(std::move(settings.folder)), file_(folder_ / (key_of(paths) + kSuffix)),
      max_bytes_(settings.max_bytes) {}

OverviewCache::~OverviewCache() { wait(); }

void OverviewCache::use(std::vector<dataset::TileSource>& sources) {
    const auto own = [](const dataset::TileSource& s) { return s.item && s.item->overview; };
    own_sidecar_ = std::any_of(sources.begin(), sources.end(), own);
    if (own_sidecar_ || max_bytes_ == 0) return;
    for (const auto& s : sources) ids_.emplace(s.path, io::display_path(s.path));
    std::error_code ec;
    if (!fs::is_regular_file(file_, ec)) return;
    fs::last_write_time(file_, fs::file_time_type::clock::now(), ec);  // (its use: the last dropped)
    const auto sidecar = std::make_shared<const std::string>(file_.string());
    for (auto& s : sources) {
        if (s.shift) continue;  // (a manifest's shifted tile: its sidecar is the manifest's own)
        auto item = s.item ? std::make_shared<dataset::CatalogItem>(*s.item) : std::make_shared<dataset::CatalogItem>();
        if (!s.item) item->href = s.path;
        item->id = ids_.at(s.path);
        item->overview = sidecar;
        s.item = std::move(item);
    }
}

std::function<void(std::uint32_t, std::vector<std::uint8_t>&&)> OverviewCache::keeper() {
    if (own_sidecar_ || max_bytes_ == 0 || ids_.empty()) return {};
    return [this](std::uint32_t tile, std::vector<std::uint8_t>&& records) {
        std::lock_guard lock(mutex_);
        if (!started_) records_[tile] = std::move(records);
    };
}

void OverviewCache::write_when_loaded(const dataset::Dataset& dataset, bool all_loaded) {
    if (!all_loaded || own_sidecar_ || ids_.empty() || started_.exchange(true)) return;
    writer_ = std::thread([this, &dataset] { write(dataset); });
}

// The tiles read (with their records and ids) as a dataset of their own; the records kept are let go.
dataset::Dataset OverviewCache::gather(const dataset::Dataset& ds, std::vector<std::string>& ids,
                                       std::vector<std::vector<std::uint8_t>>& records) {
    dataset::Dataset whole;
    whole.las_stride = ds.las_stride, whole.frame = ds.frame;
    std::lock_guard lock(mutex_);
    for (std::size_t i = 0; i < ds.tiles.size(); ++i) {
        if (!ds.is_ready(i)) continue;
        whole.tiles.push_back(ds.tiles[i]);
        whole.tiles.back().bounds_m = ds.bounds(i);
        if (ds.tiles[i].points > 0) whole.bounds_m.extend(ds.bounds(i));
        const auto id = ids_.find(ds.path(i));
        ids.push_back(id != ids_.end() ? id->second : io::display_path(ds.path(i)));
        records.push_back(records_of(ds, i, records_));
    }
    records_ = {};
    return whole;
}

// Nothing when the cached sidecar placed every tile.
void OverviewCache::write(const dataset::Dataset& ds) {
    std::size_t cached = 0;
    for (std::size_t i = 0; i < ds.tiles.size(); ++i) cached += ds.is_ready(i) && ds.tiles[i].tile.file->overview;
    if (cached == ds.tiles.size()) return finish({});
    std::string note;
    try {
        std::vector<std::string> ids;
        std::vector<std::vector<std::uint8_t>> records;
        const dataset::Dataset whole = gather(ds, ids, records);
        if (whole.tiles.empty()) return finish({});
        fs::create_directories(folder_);
        dataset::write_overview(whole, ids, records, file_.string());
        written_ = evict();
        if (!written_) {
            note = "overview cache: the sidecar of this dataset is larger than --cache-size allows; not kept";
        }
    } catch (const Error& e) {
        note = std::string("overview cache: not kept (") + e.what() + ")";
    } catch (const std::exception& e) {  // a folder that cannot be made, no memory
        note = "overview cache: not kept in " + folder_.string() + " (" + e.what() + ")";
    }
    finish(note);
}

void OverviewCache::finish(const std::string& note) {
    std::lock_guard lock(mutex_);
    note_ = note;
}

bool OverviewCache::evict() {
    struct Kept {
        fs::file_time_type used;
        fs::path path;
        std::uint64_t bytes = 0;
    };
    std::vector<Kept> kept;
    std::uint64_t total = 0;
    std::error_code ec;
    for (const auto& e : fs::directory_iterator(folder_, ec)) {
        const std::string name = e.path().filename().string();
        if (name.size() <= std::string(kSuffix).size() || !name.ends_with(kSuffix)) continue;
        const std::uint64_t bytes = e.file_size(ec);
        if (ec) continue;
        kept.push_back({e.last_write_time(ec), e.path(), bytes});
        total += bytes;
    }
    std::sort(kept.begin(), kept.end(), [](const Kept& a, const Kept& b) { return a.used < b.used; });
    const auto mine = [&](const Kept& k) { return k.path == file_; };
    for (const Kept& k : kept) {  // the least recently used first, this dataset's last
        if (total <= max_bytes_) break;
        if (mine(k)) continue;
        if (fs::remove(k.path, ec)) total -= k.bytes;
    }
    if (total <= max_bytes_) return true;
    fs::remove(file_, ec);
    return false;
}

bool OverviewCache::wait() {
    if (writer_.joinable()) writer_.join();
    return written_;
}

std::optional<std::string> OverviewCache::take_note() {
    std::lock_guard lock(mutex_);
    return std::exchange(note_, std::nullopt);
}

}  // namespace lidarscout::viewer
