// The patch grid (in core: the per-patch algorithms of recon need nothing else): a sparse 2D
// grid of square cells (640 m patches by default) into which the
// chunk points of all tiles are binned as they arrive from many I/O threads, so that the
// heightmap stage can ask for "the chunk points around this patch" (the cell +- 160 m).
//
// Precision: a float holds ~7 significant digits, so float positions relative to one origin
// lose centimetres hundreds of km away. Each point therefore stores only its offset inside
// its own cell (float, 0..patch_size: ulp <= 6.1e-5 m for a 640 m cell) and the cell key
// (int32 ix, iy) is the key of the container that holds it; absolute positions are rebuilt
// in double as origin + key * patch_size + offset. z is a float in metres (ulp 0.5 mm at
// 9,000 m, far below LIDAR noise).
#pragma once

#include <array>
#include <atomic>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <memory>
#include <mutex>
#include <span>
#include <utility>
#include <vector>

#include "core/cell_table.hpp"

namespace lidarscout {

struct Rgb8 {
    std::uint8_t r = 0, g = 0, b = 0;
    bool operator==(const Rgb8&) const = default;
};

// One chunk point as the grid stores it: 24 bytes (cell key not stored per point).
struct GridPoint {
    float dx = 0, dy = 0;  // metres from the cell's min corner, in [0, patch_size]
    float z = 0;           // metres, absolute
    std::uint32_t tile = 0;
    std::uint16_t intensity = 0;
    Rgb8 rgb;
    std::uint8_t classification = 0;
};
static_assert(sizeof(GridPoint) <= 32, "a grid point must stay within 32 bytes");

// A grid point with its position back in absolute metres (what queries return).
struct OverviewPoint {
    double x = 0, y = 0, z = 0;
    Rgb8 rgb;
    std::uint16_t intensity = 0;
    std::uint8_t classification = 0;
    std::uint32_t tile = 0;
};

class PatchGrid {
public:
    static constexpr double kDefaultPatchSize = 640.0;
    static constexpr double kDefaultPadding = 160.0;

    // Cell (ix, iy) covers [origin + ix * size, origin + (ix + 1) * size) on each axis.
    // Throws lidarscout::Error when patch_size_m is not positive and finite.
    PatchGrid(double origin_x_m, double origin_y_m, double patch_size_m = kDefaultPatchSize);
    ~PatchGrid();
    PatchGrid(const PatchGrid&) = delete;
    PatchGrid& operator=(const PatchGrid&) = delete;

    double origin_x() const { return origin_x_; }
    double origin_y() const { return origin_y_; }
    double patch_size() const { return patch_size_; }

    // Thread-safe: adds lock only the shard that owns the point's cell. Coordinates in
    // metres (the caller converts feet). Throws lidarscout::Error when the cell index does
    // not fit an int32 (more than ~1.4e12 m from the origin with 640 m cells). Returns the cell.
    CellKey add(double x_m, double y_m, double z_m, Rgb8 rgb, std::uint16_t intensity,
             std::uint8_t classification, std::uint32_t tile);

    // The points of one source in their cells (cell_of each; throws as add does), and then added: one lock and
    // one lookup for each run of points of one cell (what add costs each point). Order within a cell is kept.
    CellKey cell_of(double x_m, double y_m) const;
    GridPoint point_in(CellKey cell, double x_m, double y_m, double z_m, Rgb8 rgb, std::uint16_t intensity,
                       std::uint8_t classification, std::uint32_t tile) const;
    void add_in_cells(std::span<const std::pair<CellKey, GridPoint>> points);
    double cell_min_x(CellKey cell) const { return origin_x_ + cell.ix * patch_size_; }
    double cell_min_y(CellKey cell) const { return origin_y_ + cell.iy * patch_size_; }

    // Copy of the points stored in `cell` (empty when none), in insertion order per cell.
    std::vector<GridPoint> points_in(CellKey cell) const;
    // The same seen in place: `visit` gets them (empty when none) under the lock of the cell's shard, so it must
    // not call the grid (no copy: what a loader's callback reads of every cell a batch of tiles filled).
    void read_points(CellKey cell, const std::function<void(std::span<const GridPoint>)>& visit) const;
    // A stored point of `cell` with its position in absolute metres.
    OverviewPoint to_absolute(CellKey cell, const GridPoint& point) const;

    // The points of the padded window [min - padding, max + padding) around `cell` on both
    // axes (960 m square for the defaults), visiting the neighbouring cells it overlaps.
    std::vector<OverviewPoint> window(CellKey cell, double padding_m = kDefaultPadding) const;

    std::vector<CellKey> cells() const;  // cells holding at least one point, sorted
    std::size_t size() const { return size_.load(std::memory_order_relaxed); }

    // Heap bytes held: point storage by capacity, the shards' cell tables (core/cell_table.hpp) as they hold
    // them, plus the shards themselves. Kept as points are added (O(1): the viewer asks on every look of its
    // memory budget).
    std::size_t memory_bytes() const;
    // The same counted cell by cell (what memory_bytes must equal; for tests).
    std::size_t counted_memory_bytes() const;
    // Releases spare vector capacity (call once loading is done).
    void shrink_to_fit();

    // Bytes a cell costs beyond its points, about: its vector's header, its key and index slots, its points'
    // malloc header (a cell table's chunks hold a thousand cells each).
    static constexpr std::size_t kCellOverheadBytes =
        sizeof(std::vector<GridPoint>) + CellTable<std::vector<GridPoint>>::kBytesPerCell + 16;

private:
    struct Shard;
    static constexpr std::size_t kShardCount = 64;

    Shard& shard_for(CellKey cell) const;
    void append_window_part(CellKey centre, CellKey neighbour, double padding_m,
                            std::vector<OverviewPoint>& out) const;

    double origin_x_, origin_y_, patch_size_;
    std::unique_ptr<Shard[]> shards_;
    std::atomic<std::size_t> size_{0};
    std::atomic<std::size_t> bytes_{0};  // memory_bytes() less the shards
};

}  // namespace lidarscout
