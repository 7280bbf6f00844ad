// The points of a dataset inside an area on the ground, at full resolution: only the tiles whose
// bounds touch the area are opened and decoded, each point is placed in the dataset's frame and
// kept when it lies in the area and passes a PointFilter; a tile or LAZ chunk that
// cannot be read is named and left out. What `clip` and `profile` read (one reader for both).
#pragma once

#include <atomic>
#include <cstdint>
#include <functional>
#include <span>
#include <string>
#include <vector>

#include "core/error.hpp"
#include "dataset/dataset.hpp"
#include "core/point_filter.hpp"
#include "las/point_format.hpp"

namespace lidarscout {
class MultiPolygon;
class ThreadPool;
}  // namespace lidarscout

namespace lidarscout::pipelines {

// An area in the units of the dataset frame's CRS (as the command line gives it): the box around it,
// whether a box (a tile's bounds) shares a point with it (which tiles are read) and the test of one
// position (x, y); neither test passes outside `box`.
struct Region {
    dataset::Bounds box;
    std::function<bool(const dataset::Bounds& b)> touches;
    std::function<bool(double x, double y)> contains;
};

// xmin, ymin, xmax, ymax; edges inside.
Region box_region(double min_x, double min_y, double max_x, double max_y);
// A polygon (held by the region).
Region polygon_region(MultiPolygon polygon);
// The box a command's `option` gives (xmin, ymin, xmax, ymax: four numbers). Throws Error ("STAGE: OPTION
// ...") when they are not ordered or enclose no area.
Region bounds_region(std::span<const double> bounds, const std::string& stage, const std::string& option);

// A kept point: where it lies in the frame CRS's units (the file's coordinates as stored when the
// tile is in that CRS, else reprojected) and the record decoded.
struct RegionPoint {
    double x = 0, y = 0, z = 0;
    las::Point point;
};

// Where a tile's decoded point lies in the frame CRS's units: as stored when the tile is in that CRS
// with its units, else placed (reprojected) in metres and divided back (a region's points and the Python
// module's overview alike).
struct FrameUnits {
    FrameUnits(const dataset::DatasetTile& t, const dataset::Frame& frame)
        : tile(t), f(frame.xy_to_metres), fz(frame.z_to_metres),
          as_stored(!t.to_frame && t.xy_to_metres == f && t.z_to_metres == fz) {}

    void operator()(const las::Point& p, double& x, double& y, double& z) const {
        x = p.x, y = p.y, z = p.z;
        if (as_stored) return;
        tile.place(x, y, z);
        x /= f, y /= f, z /= fz;
    }

    const dataset::DatasetTile& tile;
    double f, fz;
    bool as_stored;
};

// Kept points of one tile, in file order: their records (the tile's record_length each, as stored)
// and the same points decoded and placed.
struct RegionBatch {
    std::uint32_t tile = 0;
    std::span<const std::uint8_t> records;
    std::span<const RegionPoint> points;
};

struct RegionReadStats {
    std::vector<std::uint32_t> tiles_touched;  // tiles whose bounds touch the region's box, in dataset order
    std::uint64_t tiles_decoded = 0;           // of them, those whose points were decoded
    std::uint64_t points_read = 0, points_kept = 0;
    std::uint64_t points_skipped = 0;          // in chunks or tiles that could not be read
    std::vector<ErrorRecord> skipped;          // those chunks and tiles, named
    bool cancelled = false;                    // stopped by ReadWatch::cancel before the end
};

// The tiles whose bounds (xy) the region touches, in dataset order. Of a dataset placed by its catalog
// (dataset/dataset.hpp) their headers are read first (ensure_tiles), and a tile that cannot be read is
// left out (the viewer's loader names it; the CLI keeps the region's tiles alone before: keep_tiles_touching).
std::vector<std::uint32_t> tiles_touching(const dataset::Dataset& ds, const Region& region);

using RegionBatchFn = std::function<void(const RegionBatch&)>;
inline constexpr std::size_t kRegionBatchPoints = std::size_t(1) << 20;
using PointProgressFn = std::function<void(std::uint64_t points_done, std::uint64_t points_total)>;
using TileProgressFn = std::function<void(std::size_t tiles_done, std::size_t tiles_total)>;

// What the caller of a read may follow and stop (from another thread): the points read of the
// touched tiles' total, the tiles finished of those touched, and a flag that, once true, ends the
// read before its next batch (about a million points; RegionReadStats::cancelled).
struct ReadWatch {
    PointProgressFn progress;
    TileProgressFn tiles;
    const std::atomic<bool>* cancel = nullptr;
    bool cancelled() const { return cancel && cancel->load(std::memory_order_relaxed); }
};

// Reads `tiles` (tiles_touching the region) one after the other, calling fn with the kept points
// of each batch (about `batch_points` points read, at least a LAZ chunk, decoded in parallel on `pool`;
// memory is a few hundred bytes a point of a batch), in file order, a piece of at most 32 Ki points
// read at a time (several calls a batch; none for a piece that keeps nothing). A tile that cannot
// be opened or placed (a point outside its CRS's area) or a LAZ chunk that cannot be decoded is
// left out and named in the result. fn may not use `pool`.
RegionReadStats read_region_points(const dataset::Dataset& ds, std::span<const std::uint32_t> tiles,
                                   const Region& region, const PointFilter& filter, ThreadPool& pool,
                                   const RegionBatchFn& fn, const ReadWatch& watch = {},
                                   std::size_t batch_points = kRegionBatchPoints);

// No silent empty product: the errors (of `stage`, e.g. "clip") of a read that finds nothing, `where`
// naming the region as its command does ("the region", "the corridor").
// Throws when `tiles` (tiles_touching the region) is empty, with the region's box and the data's
// bounds, and a hint when the box looks like degrees on projected data or the data is in degrees.
void require_touched_tiles(const dataset::Dataset& ds, std::span<const std::uint32_t> tiles, const Region& region,
                           const std::string& stage, const std::string& where);
// Throws when the read of `tiles` kept no point (stats.points_kept 0; not when cancelled), saying
// why: no point lies in the region, or none of those in it passes `filter` (how many lie in it: the
// tiles read again, unfiltered, on `pool`); points that could not be read are counted in.
void require_kept_points(const dataset::Dataset& ds, std::span<const std::uint32_t> tiles, const Region& region,
                         const PointFilter& filter, const RegionReadStats& stats, ThreadPool& pool,
                         const std::string& stage, const std::string& where);

}  // namespace lidarscout::pipelines
