// The triangle of a point set's Delaunay triangulation that holds a given position, found without
// triangulating: from the position's nearest point and that point's nearest neighbour (an edge of
// every Delaunay triangulation), a walk toward the position whose every step is a gift-wrapping
// step: the triangle across an edge is the one whose apex has the smallest circle through the
// edge, sought among the points of the square buckets that circle reaches (two levels of buckets,
// so that empty space costs little). Every triangle of the walk is a triangle of the Delaunay
// triangulation of all the points (the one CGAL builds: points on one empty circle are decided by
// CGAL's symbolic perturbation), so the answer is exact, not an approximation; a walk that leaves
// through the hull proves the position outside it.
// With a maximum edge (a TIN with no-data in longer triangles): a triangle with no edge longer
// than E holds no point farther than E / sqrt(3) from its nearest corner (one of the three angles
// at the point is at least 120 degrees, and the edge opposite it is then longer than E), so a
// position with no point that near has no value, found from the buckets around it alone.
//
// Each answer costs the points in a few circles around the position: where points are many per
// texel (a coarse DEM of dense lidar) that is far less than a triangulation of every point, and
// voids cost their rims. Exact arithmetic on the fixed-point grid (patch_space.hpp): orientations
// in 64-bit and in-circle comparisons in 128-bit integers; the tie rule of grid_geometry.hpp
// decides which triangle holds a centre on an edge, as the face map does.
#pragma once

#include <array>
#include <cstdint>
#include <span>
#include <vector>

#include "recon/patch_space.hpp"

namespace lidarscout::recon {

struct LocalTriangle {
    std::array<std::uint32_t, 3> corners{};  // indices into the positions, counter-clockwise
    std::array<double, 3> weights{};         // barycentric coordinates of the position
};

class LocalDelaunay {
public:
    // `positions`: distinct integer grid positions in [0, extent]^2 sorted by (y, x) (a patch's,
    // grid_positions); throws Error (internal) otherwise. Buckets hold about `points_per_bucket`
    // points on average over the occupied ones.
    LocalDelaunay(std::span<const GridXY> positions, std::int64_t extent, double points_per_bucket = 2.0);

    enum class Answer {
        Triangle,  // `triangle` is the triangulation's triangle over q, with no edge over the limit
        None,      // no triangle over q (q outside the hull), or one with an edge over the limit
        Unproven,  // a walk longer than `max_steps` (not met on real data; the caller triangulates)
    };
    struct Found {
        Answer answer = Answer::Unproven;
        LocalTriangle triangle;
    };

    struct Point {
        std::int64_t x, y;
        std::uint32_t index;
    };

    // Where a caller's next walk may start: the last walk's triangle, for a position next to the
    // last one where points are few per texel (where they are many, the walk from the position's
    // nearest point is shorter). Every triangle is the triangulation's, so answers do not depend
    // on it.
    struct Hint {
        std::array<const Point*, 3> last{};
        bool has_last = false;
    };

    // The triangle holding `q` (under the tie rule) if none of its edges is longer than `max_edge`
    // grid units (0: no limit); with a hint, the walk starts from its triangle and leaves the last
    // triangle in it.
    Found triangle_at(GridXY q, double max_edge, Hint* hint = nullptr, int max_steps = 4096) const;

private:
    struct Rect {
        double x0, y0, x1, y1;
    };
    // Calls visit(point) for the points of the buckets that meet `area` and that `wanted(rect)`
    // accepts (asked of each non-empty group of buckets first, then of each bucket).
    template <typename Wanted, typename Visit>
    void scan(const Rect& area, const Wanted& wanted, const Visit& visit) const;
    // The point nearest q other than `skip` (the first in scan order of equals), or nullptr when
    // none is within `limit` grid units.
    const Point* nearest(GridXY q, const Point* skip, double limit) const;
    // The apex of the Delaunay triangle left of the Delaunay edge a -> b (nullptr: a hull edge).
    const Point* wrap(const Point& a, const Point& b) const;
    // Whether no point lies left of the line a -> b (from the convex hull).
    bool nothing_left_of(const Point& a, const Point& b) const;

    std::int64_t extent_, cell_;
    long side_;                         // buckets per side
    std::vector<std::uint32_t> start_;  // bucket b's points: sorted_[start_[b], start_[b + 1])
    std::vector<Point> sorted_;
    long group_;                          // buckets per group side
    long groups_;                         // groups per side
    std::vector<std::uint32_t> grouped_;  // points per group of group_ x group_ buckets
    std::vector<Point> hull_;             // the convex hull, counter-clockwise, without collinear points
    Rect box_{1e300, 1e300, -1e300, -1e300};  // the hull's bounding box
};

}  // namespace lidarscout::recon
