// One served dataset: its tiles opened once (dataset::open_dataset), its chunk points loaded in
// the background into a patch grid (dataset::ChunkPointLoader, the viewer's loader) nearest the
// data's centre first, and the API's bodies made from them (chunk points per cell, heightmap
// patches by the viewer's linear builder, the tile list, the auto camera of `render`), encoded
// once into the server's shared cache. Nothing here knows HTTP.
#pragma once

#include <array>
#include <atomic>
#include <cstdint>
#include <functional>
#include <memory>
#include <mutex>
#include <semaphore>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "core/patch_grid.hpp"
#include "dataset/chunk_point_loader.hpp"
#include "dataset/dataset.hpp"
#include "serve/response_cache.hpp"
#include "viewer/patch_detail.hpp"

namespace lidarscout::nn {
class HeightmapNetwork;
}

namespace lidarscout::serve {

inline constexpr std::size_t kMaxCellsPerRequest = 256;
// What decoding a tile into its levels holds at its peak, per point: the decoded points (20 bytes),
// their copy sorted into blocks (20), the encoded levels and their gzip'd copies (about 10).
inline constexpr std::uint64_t kDecodeBytesPerPoint = 50;
// Heightmaps are built this many cells at a time, the client looked at between them.
inline constexpr std::size_t kHeightmapCellsPerStep = 4;

// Whether the client a body is made for has gone, polled between the steps of making it (before a
// tile is decoded, while it waits for a decoding slot, between groups of heightmaps): then the
// making stops with lidarscout::Error, nothing of it is cached, and it is counted. Empty: never.
using ClientGone = std::function<bool()>;

class Survey {
public:
    // Takes the opened dataset (at least one tile) and starts loading its chunk points. At most
    // `decode_slots` tiles are decoded at once for their levels of detail (each holds about
    // kDecodeBytesPerPoint a point meanwhile).
    Survey(dataset::Dataset dataset, ResponseCache& cache, int decode_slots = 2);
    ~Survey();
    Survey(const Survey&) = delete;
    Survey& operator=(const Survey&) = delete;

    const dataset::Dataset& dataset() const { return dataset_; }
    const PatchGrid& grid() const { return *grid_; }
    bool loaded() const { return loader_->finished(); }
    void wait_loaded() { loader_->wait(); }

    // The dataset, its frame and bounds, and the loading's progress (JSON; changes while loading).
    std::string info_json(std::size_t index) const;
    // The tiles: names (file names only, never a path), boxes in decimetres from the grid origin.
    EncodedPtr tiles();
    // The cells holding chunk points so far: uint32 count, then int32 ix, iy, uint32 points each.
    std::string cells_body() const;
    // The chunk points of `cells` (encoding.hpp) as far as they are loaded now, with `attributes`.
    EncodedPtr cell_points(std::span<const CellKey> cells, std::uint32_t attributes);
    // The heightmaps of `cells` (those with one) by the linear method or, with `cnn`, by the
    // network (set_model; its first use loads it); empty until the chunk points are loaded (a
    // heightmap's window needs its neighbours' points). Throws lidarscout::Error for cnn without a
    // model.
    // `step` > 1 sends texels that many times as large (encoding.hpp's coarsened; 1, 2, 4, 8 or 16).
    // With `detail`, the full-resolution points of the tiles decoded so far (for their levels) are
    // laid over them as render and the viewer lay them (viewer::overlay_detail): the surface under
    // real points at their height.
    std::optional<EncodedPtr> heightmaps(std::span<const CellKey> cells, bool cnn = false, int step = 1,
                                         bool detail = false, const ClientGone& gone = {});
    // The heightmap network's TorchScript file (nn/heightmap_network.hpp), loaded on first use.
    void set_model(std::string path) { model_path_ = std::move(path); }
    bool has_model() const { return !model_path_.empty(); }
    // Level `level` (0-3) of the full-resolution points of tile `tile` (encoding.hpp); the tile is
    // decoded once for its four levels. Throws lidarscout::Error for a tile or level out of range.
    EncodedPtr level(std::size_t tile, int level, std::uint32_t attributes, const ClientGone& gone = {});
    // What the expensive work has cost so far (JSON): tiles decoded, heightmaps built, requests
    // given up because their client had gone (ClientGone).
    std::string stats_json() const;
    std::uint64_t tiles_decoded() const { return tiles_decoded_; }
    std::uint64_t heightmaps_built() const { return heightmaps_built_; }
    std::uint64_t cancelled() const { return cancelled_; }
    // render's auto camera for an image of width x height and the vertical field of view (JSON),
    // looking at the whole dataset or at one of its tiles.
    std::string auto_camera_json(int width, int height, double fov_deg, std::optional<std::size_t> tile = {}) const;

private:
    std::string points_key(std::span<const CellKey> cells, std::vector<std::size_t>& counts) const;
    std::array<float, 2> intensity_range() const;
    bool has_rgb() const;  // once loaded
    void learn_detail(const viewer::PointSet& set);
    void stop_if_gone(const ClientGone& gone);
    void acquire_decode_slot(const ClientGone& gone);
    std::vector<viewer::PatchHeightmap> build_heightmaps(std::span<const CellKey> cells, bool cnn,
                                                         const ClientGone& gone);

    dataset::Dataset dataset_;
    ResponseCache& cache_;
    std::unique_ptr<PatchGrid> grid_;
    std::unique_ptr<dataset::ChunkPointLoader> loader_;
    viewer::Footprints footprints_;
    mutable std::mutex mutex_;  // the values computed once the loading is done
    mutable std::optional<bool> has_rgb_;
    mutable std::optional<std::array<float, 2>> intensity_range_;
    std::string model_path_;
    std::mutex network_mutex_;  // the network: loaded once, one inference at a time
    std::unique_ptr<nn::HeightmapNetwork> network_;
    std::counting_semaphore<> decodes_;
    std::mutex detail_mutex_;         // what the decoded tiles taught the heightmaps, per cell
    viewer::PatchDetails details_;
    std::uint64_t detail_version_ = 0;  // tiles merged into details_ (in the cache keys)
    std::uint64_t detail_bytes_ = 0;  // tiles decoded at once (each holds its points twice meanwhile)
    std::uint64_t generation_;  // distinguishes this survey's cache keys
    std::atomic<std::uint64_t> tiles_decoded_{0}, heightmaps_built_{0}, cancelled_{0};
};

}  // namespace lidarscout::serve
