// The triangle of a Delaunay triangulation that holds a given position, found from the points
// near that position alone: the points are sorted into square buckets; the buckets around the
// position are gathered ring by ring, a Delaunay triangle of the gathered points that holds the
// position is found by a walk whose every step is a gift-wrapping step (the apex over an edge
// whose circle holds no gathered point), and it is accepted when its circumcircle lies inside the
// gathered square, so that no point anywhere lies in it: it is then a triangle of the Delaunay
// triangulation of all the points (the one CGAL computes, up to the choice between the
// triangulations of points on one empty circle).
// With a maximum edge (a TIN with no-data in longer triangles) "no value" is proven as well: once
// the gathered square holds every point within the maximum edge of the position, a triangle of
// the whole triangulation with no longer edge over it would have all its corners among them and
// would be the gathered points' triangle there; so a long triangle there, or none (the position
// beyond the gathered points' hull), proves that none is short. So voids wider than the maximum
// edge are settled from the few points around them.
// What is not proven within the search's bounds (the answer "unproven": slivers along a survey's
// edge, voids near the maximum edge in size) is left to the caller, which triangulates.
//
// Where points are many per texel (a coarse DEM of dense lidar) this costs a few gathered points
// per texel instead of a triangulation of every point: a TIN's texel without the TIN. Exact
// arithmetic on the fixed-point grid (patch_space.hpp): orientations in 64-bit and in-circle
// tests in 128-bit integers; the tie rule of grid_geometry.hpp decides which triangle holds a
// centre on an edge, as the face map does.
#pragma once

#include <array>
#include <cstdint>
#include <optional>
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
    // grid_positions); throws Error (internal) otherwise.
    // Buckets hold about `points_per_bucket` points on average over the occupied ones.
    LocalDelaunay(std::span<const GridXY> positions, std::int64_t extent, double points_per_bucket = 2.0);

    enum class Answer {
        Triangle,  // `triangle` is the triangulation's triangle over q, with no edge over the limit
        None,      // no triangle over q, or one with an edge longer than the limit
        Unproven,  // neither proven within the search's bounds
    };
    struct Found {
        Answer answer = Answer::Unproven;
        LocalTriangle triangle;
    };

    // The triangle holding `q` (under the tie rule) whose edges are at most `max_edge` grid units
    // (0: no limit), from the points within about `max_points` of q.
    Found triangle_at(GridXY q, double max_edge, std::size_t max_points = 16384) const;

    // Whether q lies strictly outside the convex hull of all the positions (no triangle holds it).
    bool outside_hull(GridXY q) const;

    std::int64_t bucket_side() const { return cell_; }

    struct Point {
        std::int64_t x, y;
        std::uint32_t index;
    };

private:
    // The gathered square, in grid units (-inf / +inf on sides beyond the buckets: no point there).
    struct Region {
        double x0, y0, x1, y1;
    };
    void gather_ring(long bx, long by, int ring, std::vector<Point>& out) const;
    Region region_of(long bx, long by, int ring) const;

    std::int64_t extent_, cell_;
    long side_;                         // buckets per side
    std::vector<std::uint32_t> start_;  // bucket b's points: sorted_[start_[b], start_[b + 1])
    std::vector<Point> sorted_;
    std::vector<Point> hull_;  // counter-clockwise, without collinear points
    std::array<double, 4> box_{1e300, 1e300, -1e300, -1e300};  // the hull's: min x, min y, max x, max y
};

}  // namespace lidarscout::recon
