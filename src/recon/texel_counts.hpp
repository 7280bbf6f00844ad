// The points of a window counted per texel, with a summed-area table, so that how many lie in any
// square of texels is known at once (which texels have points near them, which lie near marked
// texels: a mask dilated by a square), and each texel's bounding box of them, so that a texel
// centre beside all the points near it (outside their convex hull) is found without them.
#pragma once

#include <cstdint>
#include <vector>

namespace lidarscout::recon {

class TexelCounts {
public:
    // `side` x `side` texels of `unit` grid units, texel (col, row) covering [col, col + 1] x [row, row
    // + 1] units (the patch grid's, patch_space.hpp).
    TexelCounts(int side, double unit);

    int side() const { return side_; }
    // One more at texel (col, row), both in [0, side), at grid position (x, y) in that texel; call
    // before summed(). Returns the count there.
    std::int64_t add(int col, int row, double x, double y);
    // Turns the counts into the summed-area table; call once, after the last add().
    void summed();
    // The count in the square of texels within `radius` (Chebyshev) of (col, row), clipped to the
    // lattice; after summed().
    std::int64_t around(int col, int row, int radius) const;
    // Whether every point within `radius` texels (Chebyshev) of texel (col, row) lies in one open
    // half-plane through its centre (tried in 16 directions on the texels' bounding boxes), so that
    // no triangle of those points holds the centre. After summed().
    bool beside(int col, int row, int radius) const;

    // Whether texel (col, row) holds a point that may lie in the closed disc of radius r around (x, y)
    // (its points' bounding box meets the disc). After summed().
    bool meets_disc(int col, int row, double x, double y, double r) const;

private:
    std::size_t index(int col, int row) const {
        return static_cast<std::size_t>(row) * (static_cast<std::size_t>(side_) + 1) + static_cast<std::size_t>(col);
    }
    struct Box {
        double x0 = 0, y0 = 0, x1 = 0, y1 = 0;
    };

    int side_;
    double unit_;
    std::vector<std::int64_t> sums_;  // (side + 1)^2: sums_[index(c, r)] = the count over [0, c) x [0, r)
    std::vector<Box> boxes_;          // side^2: the points' bounding box in each texel that has any
};

}  // namespace lidarscout::recon
