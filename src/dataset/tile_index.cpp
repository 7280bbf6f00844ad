// TileIndex: the grid of tile centres, its cells' tile lists, node boxes, and the nearest pending tile.
#include "dataset/tile_index.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace lidarscout::dataset {
namespace {

constexpr double kApartFactor = 8;       // a tile this many cells wide (or more) is kept apart
constexpr std::int64_t kMaxCells = 1 << 22;  // the grid's cells at most (the cell grows to fit)

double extent(const Bounds& b) { return std::max(b.max_x - b.min_x, b.max_y - b.min_y); }

double median_extent(std::span<const Bounds> bounds) {
    std::vector<double> e;
    for (const auto& b : bounds) {
        if (!b.empty()) e.push_back(extent(b));
    }
    if (e.empty()) return 1;
    std::nth_element(e.begin(), e.begin() + static_cast<std::ptrdiff_t>(e.size() / 2), e.end());
    return std::max(e[e.size() / 2], 1.0);
}

std::vector<Bounds> bounds_of(const Dataset& dataset) {
    std::vector<Bounds> out;
    out.reserve(dataset.tiles.size());
    for (const auto& t : dataset.tiles) out.push_back(t.bounds_m);
    return out;
}

}  // namespace

TileIndex::TileIndex(const Dataset& dataset) : TileIndex(bounds_of(dataset)) {}

TileIndex::TileIndex(std::span<const Bounds> bounds) : bounds_(bounds.begin(), bounds.end()) {
    pending_.assign(bounds_.size(), false);
    cell_m_ = median_extent(bounds_);
    Bounds centres;
    bool any_z = false;
    for (std::uint32_t t = 0; t < bounds_.size(); ++t) {
        const Bounds& b = bounds_[t];
        if (b.empty()) continue;
        if (!any_z || b.min_z < min_z_) min_z_ = b.min_z;
        if (!any_z || b.max_z > max_z_) max_z_ = b.max_z;
        any_z = true;
        if (!(extent(b) <= kApartFactor * cell_m_)) {  // NaN or infinite bounds too
            apart_.push_back(t);
            continue;
        }
        centres.extend({b.centre_x(), b.centre_y(), 0, b.centre_x(), b.centre_y(), 0});
        reach_ = std::max({reach_, 0.5 * (b.max_x - b.min_x), 0.5 * (b.max_y - b.min_y)});
    }
    if (!centres.empty()) {
        origin_x_ = centres.min_x, origin_y_ = centres.min_y;
        const auto cells = [&](double span) { return static_cast<std::int64_t>(span / cell_m_) + 1; };
        while (cells(centres.max_x - centres.min_x) * cells(centres.max_y - centres.min_y) > kMaxCells) cell_m_ *= 2;
        nx_ = static_cast<int>(cells(centres.max_x - centres.min_x));
        ny_ = static_cast<int>(cells(centres.max_y - centres.min_y));
    }
    all_ = CountQuadtree(nx_, ny_);
    pending_tree_ = CountQuadtree(nx_, ny_);
    // Counting sort of the grid's tiles by cell.
    cell_.assign(bounds_.size(), -1);
    starts_.assign(static_cast<std::size_t>(nx_) * ny_ + 1, 0);
    std::vector<bool> apart(bounds_.size(), false);
    for (const auto t : apart_) apart[t] = true;
    for (std::uint32_t t = 0; t < bounds_.size(); ++t) {
        const Bounds& b = bounds_[t];
        if (b.empty() || apart[t]) continue;
        const int x = std::clamp(static_cast<int>((b.centre_x() - origin_x_) / cell_m_), 0, nx_ - 1);
        const int y = std::clamp(static_cast<int>((b.centre_y() - origin_y_) / cell_m_), 0, ny_ - 1);
        cell_[t] = y * nx_ + x;
        ++starts_[static_cast<std::size_t>(cell_[t]) + 1];
        all_.add(x, y, 1);
    }
    for (std::size_t c = 1; c < starts_.size(); ++c) starts_[c] += starts_[c - 1];
    ids_.resize(starts_.back());
    std::vector<std::uint32_t> fill(starts_.begin(), starts_.end() - 1);
    for (std::uint32_t t = 0; t < bounds_.size(); ++t) {
        if (cell_[t] >= 0) ids_[fill[static_cast<std::size_t>(cell_[t])]++] = t;
    }
}

std::span<const std::uint32_t> TileIndex::cell_tiles(int x, int y) const {
    const std::size_t c = static_cast<std::size_t>(y) * nx_ + x;
    return std::span(ids_).subspan(starts_[c], starts_[c + 1] - starts_[c]);
}

Bounds TileIndex::node_box(const LeafRect& r) const {
    return {origin_x_ + r.x0 * cell_m_ - reach_, origin_y_ + r.y0 * cell_m_ - reach_, min_z_,
            origin_x_ + r.x1 * cell_m_ + reach_, origin_y_ + r.y1 * cell_m_ + reach_, max_z_};
}

double TileIndex::distance_xy(const LeafRect& r, double x, double y) const {
    return node_box(r).distance_xy(x, y);
}

void TileIndex::set_pending(std::uint32_t tile, bool pending) {
    if (tile >= pending_.size() || pending_[tile] == pending || bounds_[tile].empty()) return;
    pending_[tile] = pending;
    pending_total_ += pending ? 1 : -1;
    if (cell_[tile] >= 0) pending_tree_.add(cell_[tile] % nx_, cell_[tile] / nx_, pending ? 1 : -1);
}

std::optional<std::uint32_t> TileIndex::nearest_pending(double x, double y) const {
    const auto found = nearest_pending(x, y, 1);
    return found.empty() ? std::nullopt : std::optional(found.front());
}

std::vector<std::uint32_t> TileIndex::nearest_pending(double x, double y, std::size_t most) const {
    std::vector<std::uint32_t> found;
    if (most == 0) return found;
    const auto add_pending = [&](std::span<const std::uint32_t> tiles, auto& add) {
        for (const auto t : tiles) {
            ++tile_visits_;
            if (pending_[t]) add(bounds_[t].distance_xy(x, y), t);
        }
    };
    // A node's bound is the distance to its box: its tiles come out in order of their distances.
    pending_tree_.nearest_items([&](const LeafRect& r) { return distance_xy(r, x, y); },
                                [&](int cx, int cy, auto& add) { add_pending(cell_tiles(cx, cy), add); },
                                [&](auto& add) { add_pending(apart_, add); },
                                [&](std::uint32_t t) {
                                    found.push_back(t);
                                    return found.size() < most;
                                });
    return found;
}

}  // namespace lidarscout::dataset
