// The viewer's overview cache: an overview sidecar (dataset/overview_sidecar.hpp) kept for a remote
// dataset (a catalog URL, an S3 prefix, tile URLs) in the user's cache folder, so that its second open
// asks the tiles for nothing for the overview. Its file is FOLDER/KEY.overview.laz, KEY the SHA-256 of
// what was opened (the paths as shown: without credentials); its tile table's ids are the tiles' paths as
// shown. On opening, a cached sidecar names itself to every source (as a catalog's link does: the tiles
// are placed from it, their chunk points taken from it; a tile changed since is named and read itself,
// stale_tile_check). The first open keeps each tile's chunk-point records as the chunk-point loader reads
// them (keeper()), and once every tile's are in, write_when_loaded writes the sidecar on a thread of its
// own from them and the metadata bytes the tiles' opens fetched (a remote file keeps its edges), through
// a temporary name, then drops the least recently used sidecars past the bound (--cache-size). A cache
// that cannot be written, or a sidecar too large for it, is one line (note()) and the view goes on; a
// damaged cached sidecar is the dataset's warning naming it (its tiles are then read) and is written again.
#pragma once

#include <atomic>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include "dataset/dataset.hpp"

namespace lidarscout::viewer {

struct OverviewCacheSettings {
    std::filesystem::path folder;     // where the sidecars are kept
    std::uint64_t max_bytes = 2ull << 30;  // all the sidecars together at most (0: none kept)
};

class OverviewCache {
public:
    OverviewCache(const std::vector<std::string>& paths, OverviewCacheSettings settings);
    ~OverviewCache();  // waits for a write in progress
    OverviewCache(const OverviewCache&) = delete;
    OverviewCache& operator=(const OverviewCache&) = delete;

    // The cached sidecar's path for `paths` (whether or not it exists).
    const std::filesystem::path& file() const { return file_; }
    // Names the cached sidecar, when there is one, to the sources (none for a catalog with a sidecar of its own).
    void use(std::vector<dataset::TileSource>& sources);
    // What the chunk-point loader calls with each tile's records (ChunkPointLoaderOptions::on_tile_records);
    // none when this cache writes nothing (a catalog with a sidecar of its own, a bound of 0, no sources): the
    // loader then lets a sidecar's records go once its grid holds them.
    std::function<void(std::uint32_t, std::vector<std::uint8_t>&&)> keeper();
    // Once `all_loaded` (every tile's chunk points in): unless the cached sidecar placed every tile, starts
    // writing it from `dataset` (which must outlive the write, or this cache) on a thread of its own. Once.
    void write_when_loaded(const dataset::Dataset& dataset, bool all_loaded);
    // Waits for a write started; whether the sidecar was written.
    bool wait();
    // Once a write has ended: the line saying why nothing was kept ("" when all went well), the first time only.
    std::optional<std::string> take_note();

private:
    void write(const dataset::Dataset& dataset);
    dataset::Dataset gather(const dataset::Dataset& dataset, std::vector<std::string>& ids,
                            std::vector<std::vector<std::uint8_t>>& records);
    void finish(const std::string& note);  // the write ended; `note` says why nothing was kept
    bool evict();  // the least recently used sidecars past the bound dropped; whether this one is kept

    std::filesystem::path folder_, file_;
    std::uint64_t max_bytes_ = 0;
    std::map<std::string, std::string> ids_;  // a source's path -> its id in the table
    bool own_sidecar_ = false;                // the dataset has a sidecar of its own: nothing kept here
    mutable std::mutex mutex_;
    std::map<std::uint32_t, std::vector<std::uint8_t>> records_;  // by tile, as the loader read them
    std::optional<std::string> note_;  // set when the write ends
    std::atomic<bool> started_{false}, written_{false};
    std::thread writer_;
};

}  // namespace lidarscout::viewer
