// Face map against brute-force point location on random, slender and grid-aligned inputs:
// every texel centre lies in exactly one triangle of the padded triangulation under the tie
// rule, the face map names it when it is real (else -1), its barycentrics are right, and an
// independent floating-point test agrees away from edges.
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <set>

#include "recon/face_map.hpp"
#include "recon/grid_geometry.hpp"
#include "recon_test_util.hpp"

namespace lidarscout::recon {
namespace {

constexpr int kSize = 96;
constexpr double kUnit = static_cast<double>(kGridUnitsPerTexel);
constexpr std::int64_t kExtent = kSize * kGridUnitsPerTexel;

// Barycentrics in long double from the raw coordinates (independent of the library's).
std::array<long double, 3> bary_ld(const Triangulation& t, std::int32_t tri, GridXY p) {
    const auto& v = t.triangles[tri];
    const GridXY a = t.vertices[v[0]], b = t.vertices[v[1]], c = t.vertices[v[2]];
    const auto o = [](GridXY u, GridXY w, GridXY q) {
        return static_cast<long double>(w.x - u.x) * (q.y - u.y) - static_cast<long double>(w.y - u.y) * (q.x - u.x);
    };
    const long double area = o(a, b, c);
    return {o(b, c, p) / area, o(c, a, p) / area, o(a, b, p) / area};
}

// Returns the number of texel centres lying exactly on an edge or vertex (ties exercised).
int check_against_brute_force(const std::vector<GridXY>& points) {
    const Triangulation t = triangulate(points, kExtent);
    const FaceMap map = build_face_map(t, kSize);
    EXPECT_EQ(map.size, kSize);
    int ties = 0;
    for (int row = 0; row < kSize; ++row) {
        for (int col = 0; col < kSize; ++col) {
            const GridXY p{texel_centre(col), texel_centre(row)};
            const auto own = test::owners(t, p);
            EXPECT_EQ(own.size(), 1u) << "texel " << row << "," << col;
            if (own.size() != 1) continue;
            const std::int32_t expected = t.is_real(own[0]) ? own[0] : -1;
            const std::int32_t face = map.at(row, col);
            EXPECT_EQ(face, expected) << "texel " << row << "," << col;

            // Independent check: the texel lies in the named triangle (closed), and a texel
            // strictly inside some real triangle is named by it.
            bool on_edge = false;
            for (std::size_t i = 0; i < t.triangles.size(); ++i) {
                const auto l = bary_ld(t, static_cast<std::int32_t>(i), p);
                const long double lo = std::min({l[0], l[1], l[2]});
                if (lo == 0.0L) on_edge = true;
                if (lo > 1e-12L && t.is_real(i)) {
                    EXPECT_EQ(face, static_cast<std::int32_t>(i));
                }
            }
            ties += on_edge ? 1 : 0;
            if (face < 0) continue;
            const auto l = bary_ld(t, face, p);
            const std::size_t texel = static_cast<std::size_t>(row) * kSize + col;
            for (int k = 0; k < 3; ++k) {
                EXPECT_GE(l[k], -1e-12L);
                EXPECT_NEAR(static_cast<double>(l[k]), map.bary[texel][k], 1e-6);
            }
        }
    }
    return ties;
}

std::vector<GridXY> unique_points(std::vector<GridXY> points) {
    std::set<std::pair<double, double>> seen;
    std::vector<GridXY> out;
    for (const auto& p : points) {
        if (seen.insert({p.x, p.y}).second) out.push_back(p);
    }
    return out;
}

TEST(ReconFaceMap, RandomInputsMatchBruteForce) {
    for (const std::uint64_t seed : {1u, 2u, 3u, 4u}) {
        std::mt19937_64 rng(seed);
        std::uniform_int_distribution<std::int64_t> u(0, kExtent);
        std::vector<GridXY> points;
        for (int i = 0; i < 370; ++i) points.push_back({static_cast<double>(u(rng)), static_cast<double>(u(rng))});
        check_against_brute_force(unique_points(points));
    }
}

TEST(ReconFaceMap, ClusteredPointsLeaveOutsideTexels) {
    // Points in the middle only: texels far outside their hull must be -1.
    std::mt19937_64 rng(5);
    std::uniform_real_distribution<double> u(30.0 * kUnit, 60.0 * kUnit);
    std::vector<GridXY> points;
    for (int i = 0; i < 60; ++i) points.push_back({std::round(u(rng)), std::round(u(rng))});
    points = unique_points(points);
    check_against_brute_force(points);
    const FaceMap map = build_face_map(triangulate(points, kExtent), kSize);
    EXPECT_EQ(map.at(0, 0), -1);
    EXPECT_EQ(map.at(95, 95), -1);
    EXPECT_EQ(map.at(10, 50), -1);
    EXPECT_GE(map.at(45, 45), 0);
}

TEST(ReconFaceMap, SlenderTriangles) {
    // Two long, nearly parallel rows of points a fraction of a texel apart, diagonal, plus a
    // few points elsewhere: slivers much thinner than a texel that cross many texel centres.
    std::vector<GridXY> points;
    for (int i = 0; i <= 40; ++i) {
        const double s = i * 2.3 * kUnit;
        points.push_back({std::round(2 * kUnit + s), std::round(3 * kUnit + s * 0.97)});
        points.push_back({std::round(2.4 * kUnit + s * 1.001), std::round(3.1 * kUnit + s * 0.97)});
    }
    points.push_back({80 * kUnit, 10 * kUnit});
    points.push_back({10 * kUnit, 85 * kUnit});
    points.push_back({std::round(47.3 * kUnit), std::round(47.9 * kUnit)});
    check_against_brute_force(unique_points(points));

    // A fan of needles from one point.
    std::vector<GridXY> fan{{48 * kUnit, 2 * kUnit}};
    for (int i = 0; i < 30; ++i) {
        fan.push_back({std::round((20.3 + i * 1.9) * kUnit), std::round(93.7 * kUnit - (i % 2) * 17)});
    }
    check_against_brute_force(unique_points(fan));
}

TEST(ReconFaceMap, GridAlignedPointsPutTexelCentresOnEdges) {
    // Points on texel centres of a lattice: many texel centres lie exactly on edges and
    // vertices, and the lattice is cocircular (the triangulation's diagonals are arbitrary).
    std::vector<GridXY> lattice;
    for (int j = 1; j < kSize; j += 4) {
        for (int i = 1; i < kSize; i += 4) lattice.push_back({texel_centre(i), texel_centre(j)});
    }
    EXPECT_GT(check_against_brute_force(lattice), 500);

    // Points at texel corners: edges through texel centres on diagonals.
    std::vector<GridXY> corners;
    for (int j = 0; j <= kSize; j += 6) {
        for (int i = 0; i <= kSize; i += 6) corners.push_back({i * kUnit, j * kUnit});
    }
    EXPECT_GT(check_against_brute_force(corners), 100);

    // Random points snapped to half-texel positions (many collinear triples and ties).
    std::mt19937_64 rng(9);
    std::uniform_int_distribution<int> u(0, 2 * kSize);
    std::vector<GridXY> half;
    for (int i = 0; i < 300; ++i) half.push_back({u(rng) * 0.5 * kUnit, u(rng) * 0.5 * kUnit});
    EXPECT_GT(check_against_brute_force(unique_points(half)), 50);
}

TEST(ReconFaceMap, SmallWindows) {
    // Other window sizes (e.g. 1 m texels with small patches) and edge cases.
    const std::vector<GridXY> points{{0, 0}, {3.5 * kUnit, 1 * kUnit}, {1 * kUnit, 4 * kUnit}, {7 * kUnit, 7 * kUnit}};
    const Triangulation t = triangulate(points, 8 * kGridUnitsPerTexel);
    const FaceMap map = build_face_map(t, 8);
    for (int row = 0; row < 8; ++row) {
        for (int col = 0; col < 8; ++col) {
            const auto own = test::owners(t, {texel_centre(col), texel_centre(row)});
            ASSERT_EQ(own.size(), 1u);
            EXPECT_EQ(map.at(row, col), t.is_real(own[0]) ? own[0] : -1);
        }
    }
}

}  // namespace
}  // namespace lidarscout::recon
