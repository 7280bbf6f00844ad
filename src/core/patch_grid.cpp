// The patch grid: binning chunk points into 640 m cells (see patch_grid.hpp), with sharded
// locks so that many I/O threads can add at once.
#include "core/patch_grid.hpp"

#include "core/error.hpp"
#include "core/random.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

namespace lidarscout {

namespace {

std::int32_t checked_index(double scaled) {
    const double index = std::floor(scaled);
    if (!(index >= std::numeric_limits<std::int32_t>::min() &&
          index <= std::numeric_limits<std::int32_t>::max())) {
        throw Error::in_stage("dataset", "patch grid: coordinate too far from the grid origin (or NaN)");
    }
    return static_cast<std::int32_t>(index);
}

}  // namespace

struct PatchGrid::Shard {
    mutable std::mutex mutex;
    CellTable<std::vector<GridPoint>> cells;
};

PatchGrid::PatchGrid(double origin_x_m, double origin_y_m, double patch_size_m)
    : origin_x_(origin_x_m),
      origin_y_(origin_y_m),
      patch_size_(patch_size_m),
      shards_(std::make_unique<Shard[]>(kShardCount)) {
    if (!(patch_size_m > 0.0) || !std::isfinite(patch_size_m)) {
        throw Error::in_stage("dataset", "patch grid: patch size must be positive and finite");
    }
}

PatchGrid::~PatchGrid() = default;

PatchGrid::Shard& PatchGrid::shard_for(CellKey cell) const {
    // High bits pick the shard; the map's buckets use the low bits (modulo its bucket count).
    return shards_[(CellKeyHash{}(cell) >> 58) % kShardCount];
}

CellKey PatchGrid::cell_of(double x_m, double y_m) const {
    return {checked_index((x_m - origin_x_) / patch_size_),
            checked_index((y_m - origin_y_) / patch_size_)};
}

GridPoint PatchGrid::point_in(CellKey cell, double x_m, double y_m, double z_m, Rgb8 rgb, std::uint16_t intensity,
                              std::uint8_t classification, std::uint32_t tile) const {
    GridPoint p;
    p.dx = static_cast<float>((x_m - origin_x_) - cell.ix * patch_size_);
    p.dy = static_cast<float>((y_m - origin_y_) - cell.iy * patch_size_);
    p.z = static_cast<float>(z_m);
    p.rgb = rgb;
    p.intensity = intensity;
    p.classification = classification;
    p.tile = tile;
    return p;
}

CellKey PatchGrid::add(double x_m, double y_m, double z_m, Rgb8 rgb, std::uint16_t intensity,
                    std::uint8_t classification, std::uint32_t tile) {
    const CellKey cell = cell_of(x_m, y_m);
    const std::pair<CellKey, GridPoint> one{cell, point_in(cell, x_m, y_m, z_m, rgb, intensity, classification, tile)};
    add_in_cells(std::span(&one, 1));
    return cell;
}

void PatchGrid::add_in_cells(std::span<const std::pair<CellKey, GridPoint>> points) {
    for (std::size_t run = 0, end = 0; run < points.size(); run = end) {
        const CellKey cell = points[run].first;
        for (end = run + 1; end < points.size() && points[end].first == cell;) ++end;
        Shard& shard = shard_for(cell);
        std::size_t grown = 0;  // heap bytes the run adds (see memory_bytes)
        {
            std::lock_guard lock(shard.mutex);
            const std::size_t table = shard.cells.memory_bytes();
            std::vector<GridPoint>& in = shard.cells[cell];
            const std::size_t capacity = in.capacity(), need = in.size() + (end - run);
            // Grown by an eighth beyond what is needed, not doubled: a country's cells held a quarter of the grid
            // spare while it filled (100 MB of 152,100 tiles' chunk points), still amortised over many runs.
            if (need > capacity) in.reserve(need + need / 8);
            for (std::size_t k = run; k < end; ++k) in.push_back(points[k].second);
            grown = (in.capacity() - capacity) * sizeof(GridPoint) + (shard.cells.memory_bytes() - table);
        }
        bytes_.fetch_add(grown, std::memory_order_relaxed);
        size_.fetch_add(end - run, std::memory_order_relaxed);
    }
}

std::vector<GridPoint> PatchGrid::points_in(CellKey cell) const {
    const Shard& shard = shard_for(cell);
    std::lock_guard lock(shard.mutex);
    const std::vector<GridPoint>* in = shard.cells.find(cell);
    return in ? *in : std::vector<GridPoint>{};
}

void PatchGrid::read_points(CellKey cell, const std::function<void(std::span<const GridPoint>)>& visit) const {
    const Shard& shard = shard_for(cell);
    std::lock_guard lock(shard.mutex);
    const std::vector<GridPoint>* in = shard.cells.find(cell);
    visit(in ? std::span<const GridPoint>(*in) : std::span<const GridPoint>{});
}

OverviewPoint PatchGrid::to_absolute(CellKey cell, const GridPoint& p) const {
    return {cell_min_x(cell) + p.dx, cell_min_y(cell) + p.dy, p.z, p.rgb,
            p.intensity,         p.classification,           p.tile};
}

void PatchGrid::append_window_part(CellKey centre, CellKey neighbour, double padding_m,
                                   std::vector<OverviewPoint>& out) const {
    // Positions relative to the centre cell's min corner: small numbers, no cancellation.
    const double base_x = (static_cast<std::int64_t>(neighbour.ix) - centre.ix) * patch_size_;
    const double base_y = (static_cast<std::int64_t>(neighbour.iy) - centre.iy) * patch_size_;
    const double lo = -padding_m, hi = patch_size_ + padding_m;
    for (const GridPoint& p : points_in(neighbour)) {
        const double lx = base_x + p.dx, ly = base_y + p.dy;
        if (lx >= lo && lx < hi && ly >= lo && ly < hi) out.push_back(to_absolute(neighbour, p));
    }
}

std::vector<OverviewPoint> PatchGrid::window(CellKey cell, double padding_m) const {
    if (!(padding_m >= 0.0) || !std::isfinite(padding_m)) {
        throw Error::in_stage("dataset", "patch grid window: padding must be >= 0 and finite");
    }
    const auto ring = static_cast<std::int64_t>(std::ceil(padding_m / patch_size_));
    std::vector<OverviewPoint> out;
    for (std::int64_t dy = -ring; dy <= ring; ++dy) {
        for (std::int64_t dx = -ring; dx <= ring; ++dx) {
            const std::int64_t ix = cell.ix + dx, iy = cell.iy + dy;
            if (ix < std::numeric_limits<std::int32_t>::min() ||
                ix > std::numeric_limits<std::int32_t>::max() ||
                iy < std::numeric_limits<std::int32_t>::min() ||
                iy > std::numeric_limits<std::int32_t>::max()) {
                continue;
            }
            append_window_part(cell, {static_cast<std::int32_t>(ix), static_cast<std::int32_t>(iy)},
                               padding_m, out);
        }
    }
    return out;
}

std::vector<CellKey> PatchGrid::cells() const {
    std::vector<CellKey> keys;
    for (std::size_t i = 0; i < kShardCount; ++i) {
        std::lock_guard lock(shards_[i].mutex);
        const auto& cells = shards_[i].cells;
        for (std::size_t k = 0; k < cells.size(); ++k) keys.push_back(cells.key(k));
    }
    sort_cells(keys);
    return keys;
}

std::size_t PatchGrid::memory_bytes() const {
    return kShardCount * sizeof(Shard) + bytes_.load(std::memory_order_relaxed);
}

std::size_t PatchGrid::counted_memory_bytes() const {
    std::size_t bytes = kShardCount * sizeof(Shard);
    for (std::size_t i = 0; i < kShardCount; ++i) {
        std::lock_guard lock(shards_[i].mutex);
        const auto& cells = shards_[i].cells;
        bytes += cells.memory_bytes();
        for (std::size_t k = 0; k < cells.size(); ++k) bytes += cells.value(k).capacity() * sizeof(GridPoint);
    }
    return bytes;
}

void PatchGrid::shrink_to_fit() {
    for (std::size_t i = 0; i < kShardCount; ++i) {
        std::lock_guard lock(shards_[i].mutex);
        auto& cells = shards_[i].cells;
        for (std::size_t k = 0; k < cells.size(); ++k) {
            std::vector<GridPoint>& points = cells.value(k);
            const std::size_t capacity = points.capacity();
            points.shrink_to_fit();
            bytes_.fetch_sub((capacity - points.capacity()) * sizeof(GridPoint), std::memory_order_relaxed);
        }
    }
}

}  // namespace lidarscout
