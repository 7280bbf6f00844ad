// Exact nearest-point map of the texel centres, by 4 x 4 texel blocks with a candidate radius,
// the points binned into the same blocks (see nearest.hpp).
#include "recon/nearest.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

#include "recon/grid_geometry.hpp"

namespace lidarscout::recon {
namespace {

constexpr int kBlock = 4;  // texels per block side
constexpr double kBlockUnits = kBlock * static_cast<double>(kGridUnitsPerTexel);

// The points binned into blocks (counting sort: ascending index within a block).
struct Buckets {
    int blocks = 0;  // per side
    std::vector<std::int32_t> start;  // blocks * blocks + 1
    std::vector<std::int32_t> index;

    Buckets(std::span<const GridXY> points, int size) : blocks((size + kBlock - 1) / kBlock) {
        const auto cell = [&](const GridXY& p) {
            const int bx = std::min(static_cast<int>(p.x / kBlockUnits), blocks - 1);
            const int by = std::min(static_cast<int>(p.y / kBlockUnits), blocks - 1);
            return by * blocks + bx;
        };
        start.assign(static_cast<std::size_t>(blocks) * blocks + 1, 0);
        for (const GridXY& p : points) ++start[cell(p) + 1];
        for (std::size_t b = 1; b < start.size(); ++b) start[b] += start[b - 1];
        index.resize(points.size());
        std::vector<std::int32_t> next(start.begin(), start.end() - 1);
        for (std::size_t i = 0; i < points.size(); ++i) index[next[cell(points[i])]++] = static_cast<std::int32_t>(i);
    }
};

struct Block {
    int bx, by;                  // block coordinates
    int col0, col1, row0, row1;  // texel ranges [col0, col1), [row0, row1)

    GridXY centre() const {
        return {0.5 * (texel_centre(col0) + texel_centre(col1 - 1)),
                0.5 * (texel_centre(row0) + texel_centre(row1 - 1))};
    }
    double half_diagonal() const {
        const double hx = 0.5 * (texel_centre(col1 - 1) - texel_centre(col0));
        const double hy = 0.5 * (texel_centre(row1 - 1) - texel_centre(row0));
        return std::sqrt(hx * hx + hy * hy);
    }
};

// Squared distance from c to the nearest point, searching rings of blocks around block (bx, by)
// until no farther ring can hold a nearer point.
double nearest_squared(std::span<const GridXY> points, const Buckets& b, const Block& block, GridXY c) {
    double best = std::numeric_limits<double>::infinity();
    for (int ring = 0; ring < b.blocks; ++ring) {
        for (int y = std::max(block.by - ring, 0); y <= std::min(block.by + ring, b.blocks - 1); ++y) {
            const bool edge_row = y == block.by - ring || y == block.by + ring;
            for (int x = std::max(block.bx - ring, 0); x <= std::min(block.bx + ring, b.blocks - 1); ++x) {
                if (!edge_row && x != block.bx - ring && x != block.bx + ring) continue;
                const std::size_t cell = static_cast<std::size_t>(y) * b.blocks + x;
                for (std::int32_t k = b.start[cell]; k < b.start[cell + 1]; ++k) {
                    best = std::min(best, squared_distance(points[b.index[k]], c));
                }
            }
        }
        // Points of ring + 1 and beyond are at least (ring + 0.5) blocks from the block centre
        // (c is within half a texel of it on each axis for a clipped block: use ring).
        const double reach = ring * kBlockUnits;
        if (best <= reach * reach) break;
    }
    return best;
}

// Indices of the points within `radius` of c (from the blocks that the disc's box touches).
void gather(std::span<const GridXY> points, const Buckets& b, GridXY c, double radius, std::vector<std::int32_t>& out) {
    out.clear();
    const double r2 = radius * radius;
    const int x0 = std::max(static_cast<int>(std::floor((c.x - radius) / kBlockUnits)), 0);
    const int x1 = std::min(static_cast<int>(std::floor((c.x + radius) / kBlockUnits)), b.blocks - 1);
    const int y0 = std::max(static_cast<int>(std::floor((c.y - radius) / kBlockUnits)), 0);
    const int y1 = std::min(static_cast<int>(std::floor((c.y + radius) / kBlockUnits)), b.blocks - 1);
    for (int y = y0; y <= y1; ++y) {
        for (int x = x0; x <= x1; ++x) {
            const std::size_t cell = static_cast<std::size_t>(y) * b.blocks + x;
            for (std::int32_t k = b.start[cell]; k < b.start[cell + 1]; ++k) {
                if (squared_distance(points[b.index[k]], c) <= r2) out.push_back(b.index[k]);
            }
        }
    }
}

void fill_block(std::span<const GridXY> points, const Block& block, const std::vector<std::int32_t>& candidates,
                int size, std::vector<std::int32_t>& map) {
    const int width = block.col1 - block.col0;
    for (int row = block.row0; row < block.row1; ++row) {
        const double ty = texel_centre(row);
        std::array<double, kBlock> tx{}, best_d{};
        std::array<std::int32_t, kBlock> best{};
        for (int k = 0; k < kBlock; ++k) {
            tx[k] = texel_centre(block.col0 + k);
            best_d[k] = std::numeric_limits<double>::infinity();
            best[k] = -1;
        }
        for (const std::int32_t i : candidates) {  // ascending: the first of equals wins
            const double dy = points[i].y - ty, dy2 = dy * dy;
            for (int k = 0; k < kBlock; ++k) {  // the row's texels side by side (vectorisable)
                const double dx = points[i].x - tx[k];
                const double d = dx * dx + dy2;
                const bool nearer = d < best_d[k];
                best_d[k] = nearer ? d : best_d[k];
                best[k] = nearer ? i : best[k];
            }
        }
        std::copy_n(best.begin(), width, map.begin() + static_cast<std::ptrdiff_t>(row) * size + block.col0);
    }
}

}  // namespace

std::vector<std::int32_t> nearest_point_map(std::span<const GridXY> points, int size) {
    std::vector<std::int32_t> map(static_cast<std::size_t>(size) * size, -1);
    if (points.empty()) return map;
    const Buckets buckets(points, size);
    std::vector<std::int32_t> candidates;
    candidates.reserve(points.size());
    for (int by = 0; by < buckets.blocks; ++by) {
        for (int bx = 0; bx < buckets.blocks; ++bx) {
            const Block block{bx, by, bx * kBlock, std::min((bx + 1) * kBlock, size), by * kBlock,
                              std::min((by + 1) * kBlock, size)};
            const GridXY c = block.centre();
            const double d0 = std::sqrt(nearest_squared(points, buckets, block, c));
            // Slack of one part in 1e9 plus one grid unit: the radius itself is rounded.
            const double radius = (d0 + 2.0 * block.half_diagonal()) * (1.0 + 1e-9) + 1.0;
            gather(points, buckets, c, radius, candidates);
            std::sort(candidates.begin(), candidates.end());
            fill_block(points, block, candidates, size, map);
        }
    }
    return map;
}

}  // namespace lidarscout::recon
