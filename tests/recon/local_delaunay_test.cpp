// LocalDelaunay against CGAL's whole triangulation (triangulate + the face map): at every texel
// centre of random, clustered and lattice windows (a lattice puts four points on every empty
// circle: only CGAL's perturbation rule picks its triangles), the triangle found is the one the
// face map has there, "none" exactly where the face map has none or a long triangle; voids wider
// than the edge limit; a walk cut short; bad input.
#include "recon/local_delaunay.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <random>
#include <set>

#include "core/error.hpp"
#include "recon/face_map.hpp"
#include "recon/grid_geometry.hpp"
#include "recon/triangulation.hpp"

namespace lidarscout::recon {
namespace {

constexpr int kTexels = 96;
constexpr std::int64_t kExtent = kTexels * kGridUnitsPerTexel;

// Distinct positions sorted by (y, x), as a patch holds them.
std::vector<GridXY> sorted_unique(std::vector<GridXY> points) {
    std::sort(points.begin(), points.end(), [](GridXY a, GridXY b) { return a.y < b.y || (a.y == b.y && a.x < b.x); });
    points.erase(std::unique(points.begin(), points.end()), points.end());
    return points;
}

std::vector<GridXY> random_points(std::size_t n, std::uint64_t seed, double lo = 0, double hi = double(kExtent)) {
    std::mt19937_64 rng(seed);
    std::uniform_int_distribution<std::int64_t> u(static_cast<std::int64_t>(lo), static_cast<std::int64_t>(hi));
    std::vector<GridXY> out;
    for (std::size_t i = 0; i < n; ++i) out.push_back({double(u(rng)), double(u(rng))});
    return sorted_unique(out);
}

// Points on a square lattice of `step` grid units (every lattice square is cocircular), jittered
// off it with probability `jitter`.
std::vector<GridXY> lattice_points(std::int64_t step, double jitter, std::uint64_t seed) {
    std::mt19937_64 rng(seed);
    std::uniform_real_distribution<double> u(0, 1);
    std::vector<GridXY> out;
    for (std::int64_t y = step / 3; y < kExtent; y += step) {
        for (std::int64_t x = step / 5; x < kExtent; x += step) {
            const double dx = u(rng) < jitter ? std::floor(u(rng) * step / 4) : 0;
            out.push_back({double(x) + dx, double(y)});
        }
    }
    return sorted_unique(out);
}

std::set<std::uint32_t> corner_set(const std::array<std::int32_t, 3>& t) {
    return {static_cast<std::uint32_t>(t[0]), static_cast<std::uint32_t>(t[1]), static_cast<std::uint32_t>(t[2])};
}

bool long_triangle(const Triangulation& tri, std::int32_t face, double max_edge) {
    if (!(max_edge > 0)) return false;
    const auto& t = tri.triangles[face];
    for (int k = 0; k < 3; ++k) {
        if (squared_distance(tri.vertices[t[k]], tri.vertices[t[(k + 1) % 3]]) > max_edge * max_edge) return true;
    }
    return false;
}

struct Tally {
    std::size_t triangles = 0, none = 0, unproven = 0;
};

// Every texel centre of the window, row by row: the local answer against the whole triangulation's;
// with `chained`, each walk starting where the last ended.
Tally check_against_cgal(const std::vector<GridXY>& points, double max_edge, bool chained = false) {
    const Triangulation tri = triangulate(points, kExtent, /*pad_corners=*/false);
    const FaceMap map = build_face_map(tri, kTexels);
    const LocalDelaunay local(points, kExtent);
    LocalDelaunay::Hint hint;
    Tally tally;
    for (int row = 0; row < kTexels; ++row) {
        for (int col = 0; col < kTexels; ++col) {
            const GridXY q{texel_centre(col), texel_centre(row)};
            const LocalDelaunay::Found found = local.triangle_at(q, max_edge, chained ? &hint : nullptr);
            const std::int32_t face = map.at(row, col);
            const bool whole_has_value = face >= 0 && !long_triangle(tri, face, max_edge);
            switch (found.answer) {
            case LocalDelaunay::Answer::Triangle: {
                ++tally.triangles;
                EXPECT_TRUE(whole_has_value) << col << ", " << row;
                if (!whole_has_value) break;
                const auto& c = found.triangle.corners;
                EXPECT_EQ((std::set<std::uint32_t>{c[0], c[1], c[2]}), corner_set(tri.triangles[face]))
                    << col << ", " << row;
                const auto& w = found.triangle.weights;
                EXPECT_NEAR(w[0] + w[1] + w[2], 1.0, 1e-9);
                break;
            }
            case LocalDelaunay::Answer::None:
                ++tally.none;
                EXPECT_FALSE(whole_has_value) << col << ", " << row;
                break;
            case LocalDelaunay::Answer::Unproven: ++tally.unproven; break;
            }
        }
    }
    return tally;
}

TEST(LocalDelaunay, RandomPointsGiveTheWholeTriangulationsTriangles) {
    for (const std::size_t n : {2000u, 30000u, 200000u}) {  // 0.2 to 20 points per texel
        for (const bool chained : {false, true}) {
            const Tally t = check_against_cgal(random_points(n, n), 0, chained);
            EXPECT_EQ(t.unproven, 0u) << n;
            EXPECT_GT(t.triangles, 9000u) << n;  // all but the few texels beyond the hull
        }
    }
}

TEST(LocalDelaunay, LatticeTiesAreBrokenAsCgalBreaksThem) {
    // cocircular everywhere: on a pure lattice every empty circle holds four points
    for (const double jitter : {0.0, 0.3}) {
        const Tally t = check_against_cgal(lattice_points(kGridUnitsPerTexel / 2 + 7, jitter, 5), 0, jitter > 0);
        EXPECT_EQ(t.unproven, 0u) << jitter;
        EXPECT_GT(t.triangles, 9000u) << jitter;
    }
}

TEST(LocalDelaunay, ClustersAndVoidsGiveTheWholeTriangulationsTriangles) {
    // dense clusters with wide empty space between them: long triangles, voids, a ragged hull
    std::vector<GridXY> points;
    for (int c = 0; c < 12; ++c) {
        const double unit = double(kGridUnitsPerTexel);
        const double cx = (8 + (c * 37) % 80) * unit, cy = (8 + (c * 53) % 80) * unit;
        for (const GridXY& p : random_points(1500, 100 + c, 0, 6.0 * kGridUnitsPerTexel)) {
            points.push_back({cx + p.x, cy + p.y});
        }
    }
    points = sorted_unique(points);
    const Tally open = check_against_cgal(points, 0);
    EXPECT_GT(open.triangles, 4000u);  // long triangles across the voids
    EXPECT_EQ(open.unproven, 0u);
    for (const bool chained : {false, true}) {
        const Tally cut = check_against_cgal(points, 4.0 * kGridUnitsPerTexel, chained);
        EXPECT_GT(cut.none, 5000u);  // the voids between the clusters
        EXPECT_EQ(cut.unproven, 0u);
    }
}

TEST(LocalDelaunay, VoidsWiderThanTheEdgeLimitAreProvenEmpty) {
    // two dense strips 40 texels apart, an edge limit of 10 texels: every texel between is none
    std::vector<GridXY> points;
    for (const GridXY& p : random_points(60000, 9)) {
        const double col = p.x / kGridUnitsPerTexel;
        if (col < 28 || col > 68) points.push_back(p);
    }
    points = sorted_unique(points);
    const LocalDelaunay local(points, kExtent);
    for (int col = 32; col < 64; col += 3) {
        for (int row = 10; row < 86; row += 7) {
            const GridXY q{texel_centre(col), texel_centre(row)};
            EXPECT_EQ(local.triangle_at(q, 10.0 * kGridUnitsPerTexel).answer, LocalDelaunay::Answer::None)
                << col << ", " << row;
            EXPECT_EQ(local.triangle_at(q, 0).answer, LocalDelaunay::Answer::Triangle) << col << ", " << row;
        }
    }
}

TEST(LocalDelaunay, AWalkCutShortIsUnproven) {
    const std::vector<GridXY> points = random_points(30000, 4);
    const LocalDelaunay local(points, kExtent);
    std::size_t unproven = 0, triangles = 0;
    for (int col = 0; col < kTexels; col += 5) {
        const GridXY q{texel_centre(col), texel_centre(40)};
        unproven += local.triangle_at(q, 0, nullptr, 0).answer == LocalDelaunay::Answer::Unproven;
        triangles += local.triangle_at(q, 0).answer == LocalDelaunay::Answer::Triangle;
    }
    EXPECT_GT(unproven, 0u);  // the first triangle does not always hold the centre
    EXPECT_EQ(triangles, 20u);
}

TEST(LocalDelaunay, RefusesUnsortedOrOutsidePositions) {
    EXPECT_THROW(LocalDelaunay({{{5, 5}, {1, 1}}}, kExtent), lidarscout::Error);
    EXPECT_THROW(LocalDelaunay({{{1, 1}, {1, 1}}}, kExtent), lidarscout::Error);
    EXPECT_THROW(LocalDelaunay({{{1, 1}, {double(kExtent) + 1, 2}}}, kExtent), lidarscout::Error);
    EXPECT_THROW(LocalDelaunay({}, 0), lidarscout::Error);
    EXPECT_EQ(LocalDelaunay({}, kExtent).triangle_at({100, 100}, 0).answer, LocalDelaunay::Answer::None);
}

}  // namespace
}  // namespace lidarscout::recon
