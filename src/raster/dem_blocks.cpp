// dem_block_pieces: points per block from the tile headers, then recursive cuts of the grid.
#include "raster/dem_blocks.hpp"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <string>

#include "core/error.hpp"
#include "dataset/dataset.hpp"

namespace lidarscout::raster {

namespace {

// Block weights with sums over any rectangle of blocks.
class BlockWeights {
public:
    BlockWeights(const DemGrid& grid, std::vector<double> points) : grid_(grid), w_(std::move(points)) {
        for (double& v : w_) v += 1;  // an empty block still costs a little: a rectangle never weighs 0
    }

    // The weights of the rectangle's slices along x (columns) or y (rows).
    std::vector<double> slices(const BlockRange& r, bool along_x) const {
        std::vector<double> out(static_cast<std::size_t>(along_x ? r.x1 - r.x0 + 1 : r.y1 - r.y0 + 1), 0.0);
        for (int iy = r.y0; iy <= r.y1; ++iy) {
            for (int ix = r.x0; ix <= r.x1; ++ix) {
                out[static_cast<std::size_t>(along_x ? ix - r.x0 : iy - r.y0)] +=
                    w_[static_cast<std::size_t>(iy) * grid_.blocks_x() + ix];
            }
        }
        return out;
    }

private:
    const DemGrid& grid_;
    std::vector<double> w_;
};

// The best cut of `r` into pieces for `n` (>= 2): the position along the longer side (the other
// when that side is one block) and the pieces of the first part, for the least load per piece.
struct Cut {
    bool along_x = true;
    int slices_first = 0, pieces_first = 0;
};

Cut best_cut(const BlockWeights& weights, const BlockRange& r, int n) {
    const int wx = r.x1 - r.x0 + 1, wy = r.y1 - r.y0 + 1;
    Cut cut;
    cut.along_x = wy == 1 || (wx >= wy && wx > 1);
    const int length = cut.along_x ? wx : wy, across = cut.along_x ? wy : wx;
    const std::vector<double> slices = weights.slices(r, cut.along_x);
    double total = 0;
    for (const double s : slices) total += s;
    double first = 0, best = HUGE_VAL;
    for (int k = 1; k < length; ++k) {
        first += slices[static_cast<std::size_t>(k - 1)];
        const long cells_first = long(k) * across, cells_second = long(length - k) * across;
        const int lo = static_cast<int>(std::max<long>(1, n - cells_second));
        const int hi = static_cast<int>(std::min<long>(n - 1, cells_first));
        const int pieces = std::clamp(static_cast<int>(std::lround(n * first / total)), lo, hi);
        const double load = std::max(first / pieces, (total - first) / (n - pieces));
        if (load < best) best = load, cut.slices_first = k, cut.pieces_first = pieces;
    }
    return cut;
}

void split(const BlockWeights& weights, const BlockRange& r, int n, std::vector<BlockRange>& out) {
    if (n == 1) {
        out.push_back(r);
        return;
    }
    const Cut cut = best_cut(weights, r, n);
    BlockRange a = r, b = r;
    if (cut.along_x) {
        a.x1 = r.x0 + cut.slices_first - 1, b.x0 = a.x1 + 1;
    } else {
        a.y1 = r.y0 + cut.slices_first - 1, b.y0 = a.y1 + 1;
    }
    split(weights, a, cut.pieces_first, out);
    split(weights, b, n - cut.pieces_first, out);
}

int parse_positive(std::string_view text, std::string_view whole) {
    int v = 0;
    const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), v);
    if (ec != std::errc() || end != text.data() + text.size() || v < 1) {
        throw Error("--block must be I/N with 1 <= I <= N (not '" + std::string(whole) + "')");
    }
    return v;
}

}  // namespace

std::pair<int, int> parse_block_piece(std::string_view text) {
    const auto slash = text.find('/');
    if (slash == std::string_view::npos) {
        throw Error("--block must be I/N, e.g. 3/16 (not '" + std::string(text) + "')");
    }
    const int i = parse_positive(text.substr(0, slash), text), n = parse_positive(text.substr(slash + 1), text);
    if (i > n) throw Error("--block must be I/N with 1 <= I <= N (not '" + std::string(text) + "')");
    return {i, n};
}

std::vector<double> block_point_estimates(const dataset::Dataset& ds, const DemGrid& g) {
    std::vector<double> w(static_cast<std::size_t>(g.blocks_x()) * g.blocks_y(), 0.0);
    const double m = g.block * g.texel_m;
    const auto index = [&](double v, double origin, int count) {
        return std::clamp(static_cast<int>(std::floor((v - origin) / m)), 0, count - 1);
    };
    for (const auto& t : ds.tiles) {
        const auto& b = t.bounds_m;
        const double points = static_cast<double>(t.tile.header.point_count);
        const double area = (b.max_x - b.min_x) * (b.max_y - b.min_y);
        const int x0 = index(b.min_x, g.origin_x, g.blocks_x()), x1 = index(b.max_x, g.origin_x, g.blocks_x());
        const int y0 = index(b.min_y, g.origin_y, g.blocks_y()), y1 = index(b.max_y, g.origin_y, g.blocks_y());
        for (int iy = y0; iy <= y1; ++iy) {
            for (int ix = x0; ix <= x1; ++ix) {
                const double bx0 = g.origin_x + ix * m, by0 = g.origin_y + iy * m;
                const double overlap = std::max(0.0, std::min(b.max_x, bx0 + m) - std::max(b.min_x, bx0)) *
                                       std::max(0.0, std::min(b.max_y, by0 + m) - std::max(b.min_y, by0));
                // a tile without area (one line of points) goes whole to each block it touches
                w[static_cast<std::size_t>(iy) * g.blocks_x() + ix] += area > 0 ? points * overlap / area : points;
            }
        }
    }
    return w;
}

double points_in(const std::vector<double>& estimates, const DemGrid& g, const BlockRange& b) {
    double sum = 0;
    for (int iy = b.y0; iy <= b.y1; ++iy) {
        for (int ix = b.x0; ix <= b.x1; ++ix) sum += estimates[static_cast<std::size_t>(iy) * g.blocks_x() + ix];
    }
    return sum;
}

std::vector<BlockRange> dem_block_pieces(const dataset::Dataset& ds, const DemGrid& grid, int count) {
    const BlockRange all = grid.all_blocks();
    if (count < 1 || count > all.count()) {
        throw Error::in_stage("dem", "--block I/" + std::to_string(count) + ": the grid has " +
                                         std::to_string(all.count()) + " blocks of " + std::to_string(grid.block) +
                                         " x " + std::to_string(grid.block) + " texels, so N may be 1 to " +
                                         std::to_string(all.count()));
    }
    const BlockWeights weights(grid, block_point_estimates(ds, grid));
    std::vector<BlockRange> out;
    split(weights, all, count, out);
    return out;
}

}  // namespace lidarscout::raster
