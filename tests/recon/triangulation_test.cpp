// Triangulation: Delaunay (exact empty-circumcircle check), counter-clockwise triangles that
// tile the window with the padding corners, symmetric neighbours, bad input, determinism.
#include <gtest/gtest.h>

#include <algorithm>
#include <random>
#include <set>

#include "core/error.hpp"
#include "recon/grid_geometry.hpp"
#include "recon/triangulation.hpp"
#include "recon_test_util.hpp"

namespace lidarscout::recon {
namespace {

constexpr std::int64_t kExtent = 96 * kGridUnitsPerTexel;

// Exact in-circle test on integer grid coordinates: > 0 when d is strictly inside the
// circumcircle of the counter-clockwise triangle (a, b, c).
__int128 incircle(GridXY a, GridXY b, GridXY c, GridXY d) {
    const auto v = [&](GridXY p) {
        return std::array<__int128, 2>{static_cast<__int128>(p.x - d.x), static_cast<__int128>(p.y - d.y)};
    };
    const auto [adx, ady] = v(a);
    const auto [bdx, bdy] = v(b);
    const auto [cdx, cdy] = v(c);
    const __int128 alift = adx * adx + ady * ady, blift = bdx * bdx + bdy * bdy, clift = cdx * cdx + cdy * cdy;
    return alift * (bdx * cdy - bdy * cdx) - blift * (adx * cdy - ady * cdx) + clift * (adx * bdy - ady * bdx);
}

std::vector<GridXY> random_grid_points(std::size_t n, std::uint64_t seed) {
    std::mt19937_64 rng(seed);
    std::uniform_int_distribution<std::int64_t> u(0, kExtent);
    std::set<std::pair<double, double>> seen;
    std::vector<GridXY> out;
    while (out.size() < n) {
        const GridXY p{static_cast<double>(u(rng)), static_cast<double>(u(rng))};
        if (seen.insert({p.x, p.y}).second) out.push_back(p);
    }
    return out;
}

void check_triangulation(const std::vector<GridXY>& points, const Triangulation& t) {
    ASSERT_EQ(t.real_count, points.size());
    for (std::size_t i = 0; i < points.size(); ++i) ASSERT_EQ(t.vertices[i], points[i]);
    __int128 area2 = 0;
    std::vector<int> used(t.vertices.size(), 0);
    for (std::size_t i = 0; i < t.triangles.size(); ++i) {
        const auto& tri = t.triangles[i];
        const double o = orient(t.vertices[tri[0]], t.vertices[tri[1]], t.vertices[tri[2]]);
        ASSERT_GT(o, 0.0) << "triangle " << i << " is not counter-clockwise";
        area2 += static_cast<__int128>(o);
        for (int k = 0; k < 3; ++k) {
            ++used[tri[k]];
            const std::int32_t nb = t.neighbours[i][k];
            if (nb < 0) continue;
            // The neighbour shares the edge opposite vertex k and points back.
            const auto& other = t.neighbours[nb];
            EXPECT_NE(std::find(other.begin(), other.end(), static_cast<std::int32_t>(i)), other.end());
        }
        for (std::size_t v = 0; v < t.vertices.size(); ++v) {
            ASSERT_LE(incircle(t.vertices[tri[0]], t.vertices[tri[1]], t.vertices[tri[2]], t.vertices[v]), 0)
                << "vertex " << v << " inside the circumcircle of triangle " << i;
        }
    }
    // The triangles tile the window exactly (the padding corners make the hull the window).
    EXPECT_TRUE(area2 == 2 * static_cast<__int128>(kExtent) * kExtent);  // orient = twice the area
    for (std::size_t v = 0; v < t.vertices.size(); ++v) EXPECT_GT(used[v], 0) << "vertex " << v;
}

TEST(ReconTriangulation, RandomPointsAreDelaunayAndTileTheWindow) {
    for (const std::uint64_t seed : {1u, 2u, 3u}) {
        const auto points = random_grid_points(300, seed);
        const Triangulation t = triangulate(points, kExtent);
        EXPECT_EQ(t.vertices.size(), points.size() + 4);
        check_triangulation(points, t);
    }
}

TEST(ReconTriangulation, LatticeWithPointsOnCornersAndEdges) {
    // Cocircular lattice including the window corners: no padding point is added there.
    std::vector<GridXY> points;
    for (int j = 0; j <= 12; ++j) {
        for (int i = 0; i <= 12; ++i) points.push_back({i * 8.0 * kGridUnitsPerTexel, j * 8.0 * kGridUnitsPerTexel});
    }
    const Triangulation t = triangulate(points, kExtent);
    EXPECT_EQ(t.vertices.size(), points.size());
    check_triangulation(points, t);
    for (std::size_t i = 0; i < t.triangles.size(); ++i) EXPECT_TRUE(t.is_real(i));
}

TEST(ReconTriangulation, FewPoints) {
    const std::vector<GridXY> none;
    const Triangulation empty = triangulate(none, kExtent);
    EXPECT_EQ(empty.triangles.size(), 2u);
    check_triangulation(none, empty);
    const std::vector<GridXY> one{{1000.0, 2000.0}};
    const Triangulation single = triangulate(one, kExtent);
    EXPECT_EQ(single.triangles.size(), 4u);
    check_triangulation(one, single);
}

TEST(ReconTriangulation, RejectsBadInput) {
    const std::vector<GridXY> repeated{{10, 10}, {20, 20}, {10, 10}};
    EXPECT_THROW(triangulate(repeated, kExtent), Error);
    const std::vector<GridXY> outside{{10, 10}, {kExtent + 1.0, 20}};
    EXPECT_THROW(triangulate(outside, kExtent), Error);
}

TEST(ReconTriangulation, Deterministic) {
    std::vector<GridXY> points;
    for (int j = 0; j < 10; ++j) {
        for (int i = 0; i < 10; ++i) points.push_back({(i * 9 + 3) * 65536.0, (j * 9 + 3) * 65536.0});
    }
    const Triangulation a = triangulate(points, kExtent);
    for (int run = 0; run < 3; ++run) {
        const Triangulation b = triangulate(points, kExtent);
        EXPECT_EQ(a.triangles, b.triangles);
        EXPECT_EQ(a.neighbours, b.neighbours);
    }
}

}  // namespace
}  // namespace lidarscout::recon
