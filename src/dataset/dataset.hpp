// A dataset = the tiles a user opened (folders, tile lists, files): their metadata read in
// parallel, each tile's bounds in metres (patch geometry is metric), the files that could
// not be used with their one-line errors, and warnings about the whole (mixed CRSs, missing
// units). Nothing here reads point data.
//
// A dataset placed by its catalog (DatasetOptions::placed: a STAC catalog whose every item gives
// pc:count, proj:bbox and a CRS PROJ knows, in the frame's CRS) opens from its items at once, without
// reading a tile: each tile's header, records and chunk table are read on demand (Dataset::ready,
// ensure_tiles), once, from any thread. Until then a tile holds only what its item says (bounds_m,
// points, chunk_points: its "placed" fields, never written again while the dataset is shared) and
// its `tile` must not be used; Dataset::is_ready says when it may. A tile read whose header disagrees
// with its item is corrected at once where other threads look (Dataset::bounds: the header's bounds from
// then on) and named (Dataset::corrections: the line settle_tiles puts in `warnings`), so that a viewer
// sees it while the dataset is shared. settle_tiles (a caller that holds the dataset alone, as the CLI
// does) then corrects the placed fields themselves from the headers read and moves the tiles that could
// not be read to `skipped`.
#pragma once

#include <atomic>
#include <cstdint>
#include <functional>
#include <limits>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <utility>
#include <vector>

#include "core/diagnostic.hpp"
#include "dataset/file_search.hpp"
#include "dataset/tile.hpp"

namespace lidarscout::geo {
class CrsTransform;
}

namespace lidarscout::dataset {

// An axis-aligned box in metres; empty until extended.
struct Bounds {
    double min_x = std::numeric_limits<double>::infinity();
    double min_y = std::numeric_limits<double>::infinity();
    double min_z = std::numeric_limits<double>::infinity();
    double max_x = -std::numeric_limits<double>::infinity();
    double max_y = -std::numeric_limits<double>::infinity();
    double max_z = -std::numeric_limits<double>::infinity();

    bool empty() const { return !(min_x <= max_x); }
    void extend(const Bounds& other);
    // Distance in the xy plane from (x, y) to the box (0 inside).
    double distance_xy(double x, double y) const;
    double centre_x() const { return 0.5 * (min_x + max_x); }
    double centre_y() const { return 0.5 * (min_y + max_y); }
};

struct DatasetTile {
    Tile tile;
    double xy_to_metres = 1.0;  // file units -> metres, horizontal (1 for a tile in degrees: see Frame)
    double z_to_metres = 1.0;   // file units -> metres, vertical
    Bounds bounds_m;            // the header's bounds, in metres (of the dataset's frame); a placed tile's: its item's
    std::uint64_t chunk_points = 0;  // a placed tile's: estimated from its item's pc:count (DatasetOptions::las_stride)
    std::uint64_t points = 0;   // the header's point count; a placed tile's: its item's pc:count
    // Set when the tile's CRS is not the dataset's: file units -> the frame CRS's units (x, y),
    // then frame_xy_to_metres. Heights go through it too when both CRSs have a vertical part
    // (heights_to_frame: z then ends in the frame's vertical unit); else z keeps the file's.
    std::shared_ptr<const geo::CrsTransform> to_frame;
    double frame_xy_to_metres = 1.0;
    bool heights_to_frame = false;
    double frame_z_to_metres = 1.0;

    // Metres per unit of z as place() has it before scaling: the frame's vertical unit when heights
    // are transformed, else the file's.
    double placed_z_to_metres() const { return heights_to_frame ? frame_z_to_metres : z_to_metres; }

    // A point's coordinates as stored (x, y, z of las::Point) -> metres of the dataset's frame.
    // Throws Error (stage "geo") when a reprojected point lies outside the CRSs' area.
    void place(double& x, double& y, double& z) const {
        if (to_frame) return place(std::span<double>(&x, 1), std::span<double>(&y, 1), std::span<double>(&z, 1));
        x *= xy_to_metres, y *= xy_to_metres, z *= z_to_metres;  // the common case, inline (per point)
    }
    void place(std::span<double> x, std::span<double> y, std::span<double> z) const;
};

// The CRS the dataset's metres are in: the tiles' CRS (the majority's when they differ, or the
// one asked for) and its native units, so that outputs (DEMs) can be written in that CRS's own
// units. Tiles in another CRS are reprojected into it with PROJ (DatasetTile::to_frame); tiles
// without a CRS are taken to be in it.
struct Frame {
    std::string crs;            // definition for PROJ/GDAL (geo/crs_definition.hpp); "" when unknown
    double xy_to_metres = 1.0;  // native horizontal unit -> metres
    double z_to_metres = 1.0;   // native vertical unit -> metres
    // x/y are degrees (longitude, latitude; DatasetOptions::accept_degrees): the "metres" of the
    // dataset (bounds_m, DatasetTile::place) are then degrees, xy_to_metres 1.
    bool geographic = false;
};

class PlacedTiles;  // the tiles of a dataset placed by its catalog, read on demand (dataset.cpp)

struct Dataset {
    std::vector<DatasetTile> tiles;   // in the order the paths were given / found
    std::vector<SkippedFile> skipped;
    Diagnostics warnings;
    Bounds bounds_m;
    Frame frame;
    std::uint64_t point_count = 0;
    std::uint64_t chunk_point_count = 0;
    std::uint64_t las_stride = 50'000;  // chunk-point stride used for uncompressed LAS tiles
    // Set when the dataset was placed by its catalog (see the top of this file); null when every tile
    // was read as it opened. A copy shares it: copy a placed dataset only once settle_tiles made it whole.
    std::shared_ptr<PlacedTiles> placed;

    // Whether tile i's header is read and usable: its `tile` may be used (always, in a dataset not placed).
    bool is_ready(std::size_t i) const;
    // Reads tile i's header, records and chunk table once (the callers of other threads wait for that
    // read); false when it cannot be read (ready_error says why). Thread-safe.
    bool ready(std::size_t i) const;
    // The line naming why tile i could not be read ("" when it was, or was not tried yet).
    std::string ready_error(std::size_t i) const;
    // Tile i's path or URL (known before its header is read).
    const std::string& path(std::size_t i) const;
    // The tiles whose headers are read (tiles not placed count as read).
    std::size_t tiles_ready() const;
    // Tile i's bounds as known now: its header's once it is read (is_ready), else its item's (bounds_m).
    // Thread-safe; what a viewer draws, picks and ranks tiles by.
    const Bounds& bounds(std::size_t i) const;
    // The lines naming the tiles read so far whose headers disagree with their items (the header's values
    // used: item_disagreement), in the order they were read, from the `from`-th on. Thread-safe; the same
    // lines settle_tiles puts in `warnings` (after which there are none here).
    Diagnostics corrections(std::size_t from = 0) const;
    std::size_t corrections_count() const;
};

struct DatasetOptions {
    unsigned io_threads = 16;  // header reads in flight (I/O bound: more than the cores)
    std::uint64_t las_stride = 50'000;  // chunk-point stride for uncompressed LAS tiles
    std::string crs;  // the frame's CRS ("EPSG:32632", WKT); empty: the CRS most tiles use
    // Whether the frame may be in degrees (a caller that works in the CRS's units, as clip does).
    // Without it, tiles in degrees are reprojected into a projected frame (the CRS asked for, else
    // the one most projected tiles use), a geographic `crs` is refused, and with no projected CRS to
    // go to they are skipped naming the --crs to give (the UTM zone of the data's centre).
    bool accept_degrees = false;
    // Called once the paths are expanded, before any header is read: the tiles to read (a STAC
    // catalog's with what its items say of them: catalog_footprint places them at once).
    std::function<void(std::span<const TileSource>)> sources_found;
    // Called from reader threads as files finish: (files done, files total).
    std::function<void(std::size_t, std::size_t)> progress;
    // Called from reader threads for each tile read, before `progress` counts it (a tile in
    // another CRS than the frame's still has its bounds in its own CRS's metres, or degrees, here).
    std::function<void(const DatasetTile&)> tile_read;
    // When it turns true, files not yet started are not read and open_dataset throws Error
    // ("opening cancelled") once the reads in progress have ended.
    const std::atomic<bool>* cancel = nullptr;
    // Whether a catalog whose items place every tile opens placed (see the top of this file): for callers
    // that read headers on demand (ready, ensure_tiles) or settle_tiles before using them.
    bool placed = false;
    // Whether a catalog's overview sidecar (dataset/overview_sidecar.hpp) places the tiles it holds
    // (their chunk points then come from it, and their files are not read to open them).
    bool use_overview = true;
};

// Whether open_sources uses overview sidecars at all (DatasetOptions::use_overview then decides per
// call): the CLI's --no-overview turns them off for the process.
void use_overview_sidecars(bool used);
bool overview_sidecars_in_use();

// Finds and reads the tiles of `paths` (files, folders, tile lists, and virtual replica
// manifests: dataset/virtual_replica.hpp). Never throws for a bad file: it lands in `skipped`;
// throws only when options.cancel asked it to stop.
Dataset open_dataset(const std::vector<std::string>& paths, const DatasetOptions& options = {});
// Whether open_sources of `sources` with `options` opens the dataset placed by their catalog.
bool opens_placed(std::span<const TileSource> sources, const DatasetOptions& options);
// open_dataset of sources found already (find_tile_sources).
Dataset open_sources(FoundSources found, const DatasetOptions& options = {});

// Reads the headers of the tiles `indices` not read yet (Dataset::ready), in parallel on the header
// reads' threads (DatasetOptions::io_threads), started in the order given. Thread-safe; nothing for a
// dataset not placed.
void ensure_tiles(const Dataset& dataset, std::span<const std::uint32_t> indices, unsigned io_threads = 16);
// ensure_tiles of every tile.
void ensure_all_tiles(const Dataset& dataset, unsigned io_threads = 16);
// For a caller that holds the dataset alone (no other thread uses it): the tiles read so far take their
// headers' bounds, counts and chunk points (a disagreement with the item named in `warnings`, once),
// those that could not be read move to `skipped`, and the dataset's bounds and counts follow. Tile
// indices change when a tile is dropped. Once every tile is read, `placed` is released.
void settle_tiles(Dataset& dataset);

// For a caller that holds the dataset alone and works on a region: reads the headers of the tiles whose
// footprints `touches` passes (x/y in the frame CRS's units, as a pipelines::Region takes them), settles
// them, and drops the others (outside the region): the dataset is then one read whole, of the region's
// tiles. Nothing for a dataset not placed.
void keep_tiles_touching(Dataset& dataset, const std::function<bool(const Bounds&)>& touches,
                         unsigned io_threads = 16);

// catalog_footprint of each source (empty for a source no catalog item places).
std::vector<std::optional<Bounds>> catalog_footprints(std::span<const TileSource> sources);

// The sources nearest to the centre of a catalog's extent, where their items place them
// (`footprints`: catalog_footprints of the sources; the tiles a viewer can show first while the rest
// of a large catalog opens): those within `radius_m` of the centre, nearest first, at most `most`.
// Empty unless every source has a catalog footprint.
std::vector<TileSource> central_sources(std::span<const TileSource> sources,
                                        std::span<const std::optional<Bounds>> footprints, double radius_m,
                                        std::size_t most);

// Where a STAC catalog item says its tile lies, in metres of the item's CRS (its proj:bbox scaled by
// the CRS's units; z from 0 when the bbox is 2D): the tile's footprint before its header is read.
// Empty without a bbox, or with a CRS PROJ does not know or in degrees.
std::optional<Bounds> catalog_footprint(const CatalogItem& item);

// Throws Error (of `stage`) when the dataset has no readable tile, naming why: the first skipped
// paths with their causes and how many more there are.
void require_tiles(const Dataset& dataset, const std::string& stage);

// The patch grid origin for a dataset: its min corner rounded down to a multiple of
// `patch_size_m`, so patches fall on the same metric lattice whatever tiles are opened.
std::pair<double, double> patch_grid_origin(const Dataset& dataset, double patch_size_m = 640.0);

// Wraps a tile already read: unit factors and bounds in metres (in degrees for a tile in degrees,
// xy_to_metres 1, z in its vertical unit or metres).
DatasetTile make_dataset_tile(Tile tile, std::uint64_t las_stride = 50'000);

}  // namespace lidarscout::dataset
