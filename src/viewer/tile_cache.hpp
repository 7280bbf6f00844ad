// The full-resolution tiles the scheduler holds in memory: each tile's decoded points (shared
// with the frames that draw them), when the camera last wanted it, and the choice of tiles to
// release, least recently seen first, so that a new tile fits in the memory budget. Not
// thread-safe: the scheduler guards it with its own lock.
#pragma once

#include <cstdint>
#include <map>
#include <memory>
#include <optional>
#include <span>
#include <vector>

#include "viewer/point_sets.hpp"

namespace lidarscout::viewer {

class TileCache {
public:
    bool contains(std::uint32_t tile) const { return tiles_.contains(tile); }
    std::size_t size() const { return tiles_.size(); }
    std::uint64_t bytes() const { return bytes_; }
    std::uint64_t points() const { return points_; }

    // Adds a decoded tile, seen at `tick` (a counter the caller increases as the camera moves).
    void insert(std::uint32_t tile, std::shared_ptr<const PointSet> points, std::uint64_t tick);
    // Records that the camera wants `tile` at `tick` (no-op for a tile not held).
    void touch(std::uint32_t tile, std::uint64_t tick);
    // Drops the tile and returns its points (null when not held).
    std::shared_ptr<const PointSet> release(std::uint32_t tile);

    // Tiles to release, least recently seen first (ties: the larger first), so that
    // `other_bytes` + what stays + `incoming` fits in `budget`; tiles in `keep` are never chosen.
    // nullopt when it cannot fit even after releasing every tile not kept.
    std::optional<std::vector<std::uint32_t>> victims(std::uint64_t incoming, std::uint64_t other_bytes, std::uint64_t budget,
                                       std::span<const std::uint32_t> keep) const;

    std::vector<std::uint32_t> tiles() const;
    // The points of every held tile (for drawing).
    std::vector<std::shared_ptr<const PointSet>> point_sets() const;

    // Bytes a decoded point set holds.
    static std::uint64_t bytes_of(const PointSet& set) { return set.points.capacity() * sizeof(render::PointAttr); }

private:
    struct Entry {
        std::shared_ptr<const PointSet> points;
        std::uint64_t bytes = 0;
        std::uint64_t last_seen = 0;
    };
    std::map<std::uint32_t, Entry> tiles_;
    std::uint64_t bytes_ = 0, points_ = 0;
};

}  // namespace lidarscout::viewer
