// TileCache: resident full-resolution tiles and the least-recently-seen release order.
#include "viewer/tile_cache.hpp"

#include <algorithm>

namespace lidarscout::viewer {

void TileCache::insert(std::uint32_t tile, std::shared_ptr<const PointSet> points, std::uint64_t tick) {
    release(tile);
    const std::uint64_t bytes = bytes_of(*points);
    bytes_ += bytes;
    points_ += points->points.size();
    tiles_[tile] = {std::move(points), bytes, tick};
}

void TileCache::touch(std::uint32_t tile, std::uint64_t tick) {
    const auto it = tiles_.find(tile);
    if (it != tiles_.end()) it->second.last_seen = std::max(it->second.last_seen, tick);
}

std::shared_ptr<const PointSet> TileCache::release(std::uint32_t tile) {
    const auto it = tiles_.find(tile);
    if (it == tiles_.end()) return nullptr;
    auto points = std::move(it->second.points);
    bytes_ -= it->second.bytes;
    points_ -= points->points.size();
    tiles_.erase(it);
    return points;
}

std::optional<std::vector<std::uint32_t>> TileCache::victims(std::uint64_t incoming, std::uint64_t other_bytes, std::uint64_t budget,
                                              std::span<const std::uint32_t> keep) const {
    std::vector<std::pair<std::uint32_t, const Entry*>> candidates;
    for (const auto& [tile, entry] : tiles_) {
        if (std::find(keep.begin(), keep.end(), tile) == keep.end()) candidates.emplace_back(tile, &entry);
    }
    std::sort(candidates.begin(), candidates.end(), [](const auto& a, const auto& b) {
        if (a.second->last_seen != b.second->last_seen) return a.second->last_seen < b.second->last_seen;
        return a.second->bytes > b.second->bytes;
    });
    std::vector<std::uint32_t> out;
    std::uint64_t held = bytes_;
    for (const auto& [tile, entry] : candidates) {
        if (other_bytes + held + incoming <= budget) break;
        out.push_back(tile);
        held -= entry->bytes;
    }
    if (other_bytes + held + incoming > budget) return std::nullopt;
    return out;
}

std::vector<std::uint32_t> TileCache::tiles() const {
    std::vector<std::uint32_t> out;
    for (const auto& [tile, entry] : tiles_) out.push_back(tile);
    return out;
}

std::vector<std::shared_ptr<const PointSet>> TileCache::point_sets() const {
    std::vector<std::shared_ptr<const PointSet>> out;
    out.reserve(tiles_.size());
    for (const auto& [tile, entry] : tiles_) out.push_back(entry.points);
    return out;
}

}  // namespace lidarscout::viewer
