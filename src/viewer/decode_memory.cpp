// Decode memory: the bytes per point of a piece, the largest decode unit, the piece size that fits.
#include "viewer/decode_memory.hpp"

#include <algorithm>

#include "render/point_batch.hpp"

namespace lidarscout::viewer {
namespace {

// Building blocks from a piece: which block each point is in and the points grouped by block
// (4 + 4), and for each block being built its sort keys twice over (8 + 8), heights (4) and
// levels (1).
constexpr std::uint64_t kBlockScratchPerPoint = 4 + 4 + 8 + 8 + 4 + 1;

bool one_piece(const dataset::DatasetTile& t) {
    return !t.tile.compressed() || !t.tile.chunks() || !t.tile.laz() || t.tile.chunks()->empty();
}

}  // namespace

std::uint64_t piece_bytes_per_point(const dataset::DatasetTile& tile) {
    const std::uint64_t attr = sizeof(render::PointAttr);
    const std::uint64_t decoding = tile.tile.header.record_length + attr;
    const std::uint64_t building = attr + kBlockScratchPerPoint;
    return std::max(decoding, building);
}

std::uint64_t largest_unit_points(const dataset::DatasetTile& tile) {
    if (one_piece(tile)) return tile.tile.header.point_count;
    std::uint64_t largest = 0;
    for (const auto& c : *tile.tile.chunks()) largest = std::max(largest, c.point_count);
    return largest;
}

DecodePlan decode_plan(const dataset::DatasetTile& tile, std::uint64_t points, unsigned threads,
                       std::uint64_t piece_points) {
    piece_points = std::max<std::uint64_t>(piece_points, 1);
    const std::uint64_t unit = largest_unit_points(tile);
    // A piece takes units while it has fewer than piece_points: at most piece_points - 1 + one unit.
    const std::uint64_t piece = std::min(points, piece_points - 1 + unit);
    const std::uint64_t pieces = one_piece(tile) ? 1 : (points + piece_points - 1) / piece_points;
    const std::uint64_t busy = std::clamp<std::uint64_t>(pieces, 1, std::max(1u, threads));
    return {piece_points, busy * piece * piece_bytes_per_point(tile)};
}

std::optional<DecodePlan> fitting_decode_plan(const dataset::DatasetTile& tile, std::uint64_t points, unsigned threads,
                                              std::uint64_t max_piece_points, std::uint64_t room) {
    for (std::uint64_t p = std::max<std::uint64_t>(max_piece_points, 1);; p /= 2) {
        const DecodePlan plan = decode_plan(tile, points, threads, p);
        if (plan.transient <= room) return plan;
        if (p == 1) return std::nullopt;
    }
}

}  // namespace lidarscout::viewer
