// The summed-area table, the bounding boxes and the half-plane test of texel_counts.hpp.
#include "recon/texel_counts.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>

#include "core/error.hpp"

namespace lidarscout::recon {

TexelCounts::TexelCounts(int side, double unit) : side_(side), unit_(unit) {
    if (side < 1 || side > 65536 || !(unit > 0)) {
        throw Error::in_stage("recon", "texel counts: bad lattice (internal error)");
    }
    sums_.assign((static_cast<std::size_t>(side) + 1) * (static_cast<std::size_t>(side) + 1), 0);
    boxes_.resize(static_cast<std::size_t>(side) * side);
}

std::int64_t TexelCounts::add(int col, int row, double x, double y) {
    const std::int64_t count = ++sums_[index(col + 1, row + 1)];
    Box& b = boxes_[static_cast<std::size_t>(row) * side_ + col];
    if (count == 1) b = {x, y, x, y};
    else b = {std::min(b.x0, x), std::min(b.y0, y), std::max(b.x1, x), std::max(b.y1, y)};
    return count;
}

void TexelCounts::summed() {
    for (int r = 1; r <= side_; ++r) {
        for (int c = 1; c <= side_; ++c) {
            sums_[index(c, r)] += sums_[index(c - 1, r)] + sums_[index(c, r - 1)] - sums_[index(c - 1, r - 1)];
        }
    }
}

std::int64_t TexelCounts::around(int col, int row, int radius) const {
    const int c0 = std::clamp(col - radius, 0, side_), c1 = std::clamp(col + radius + 1, 0, side_);
    const int r0 = std::clamp(row - radius, 0, side_), r1 = std::clamp(row + radius + 1, 0, side_);
    return sums_[index(c1, r1)] - sums_[index(c0, r1)] - sums_[index(c1, r0)] + sums_[index(c0, r0)];
}

bool TexelCounts::meets_disc(int col, int row, double x, double y, double r) const {
    if (around(col, row, 0) == 0) return false;
    const Box& b = boxes_[static_cast<std::size_t>(row) * side_ + col];
    const double dx = std::max({b.x0 - x, 0.0, x - b.x1}), dy = std::max({b.y0 - y, 0.0, y - b.y1});
    return dx * dx + dy * dy <= r * r;
}

bool TexelCounts::beside(int col, int row, int radius) const {
    constexpr int kDirections = 16;
    static const auto u = [] {
        std::array<std::array<double, 2>, kDirections> out{};
        for (int k = 0; k < kDirections; ++k) {
            const double a = 2.0 * std::numbers::pi * k / kDirections;
            out[k] = {std::cos(a), std::sin(a)};
        }
        return out;
    }();
    std::array<bool, kDirections> open{};  // no box so far reaches the side of the centre u[k] points to
    open.fill(true);
    const double qx = (col + 0.5) * unit_, qy = (row + 0.5) * unit_;
    // whether some direction stays open after the points of texel (c, r)
    const auto still_open = [&](int c, int r) {
        if (c < 0 || r < 0 || c >= side_ || r >= side_ || around(c, r, 0) == 0) return true;
        const Box& b = boxes_[static_cast<std::size_t>(r) * side_ + c];
        bool any = false;
        for (int k = 0; k < kDirections; ++k) {
            const double x = u[k][0] > 0 ? b.x1 : b.x0, y = u[k][1] > 0 ? b.y1 : b.y0;  // the farthest corner
            open[k] = open[k] && u[k][0] * (x - qx) + u[k][1] * (y - qy) < -1e-6 * unit_;
            any = any || open[k];
        }
        return any;
    };
    // ring by ring from the texel out, so that points all around close every direction early
    for (int k = 0; k <= radius; ++k) {
        for (int d = -k; d <= k; ++d) {
            if (!still_open(col + d, row - k) || (k > 0 && !still_open(col + d, row + k))) return false;
        }
        for (int d = -k + 1; d <= k - 1; ++d) {
            if (!still_open(col - k, row + d) || !still_open(col + k, row + d)) return false;
        }
    }
    return true;
}

}  // namespace lidarscout::recon
