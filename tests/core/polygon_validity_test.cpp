// core/polygon_validity: a bow tie, a pentagram drawn in one stroke and a hole crossing its outer ring
// are named at a crossing, in one line with the rule applied; outlines that do not cross (a square with
// a hole, rings touching at a vertex, overlapping parts of a multipolygon, a repeated vertex) are quiet;
// the sweep agrees with a brute force over every pair of edges on 20,000 small polygons on an integer
// grid (touching, collinear and repeated vertices everywhere) and 2,000 star-shaped ones, and costs
// work linear-logarithmic in the vertices (counted) on 100k-vertex circles, zigzags and stars whose
// spikes meet at the centre -- where a grid of edges would test billions of pairs.
#include "core/polygon_validity.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <optional>
#include <random>

#include "core/error.hpp"
#include "polygon_shapes.hpp"

namespace lidarscout {
namespace {

TEST(PolygonValidity, ABowTieIsNamedAtItsCrossing) {
    const auto check = find_crossing(parse_wkt_polygon("POLYGON ((0 0, 2 2, 2 0, 0 2, 0 0))"));
    ASSERT_TRUE(check.first);
    EXPECT_EQ(check.first->part, 0u);
    EXPECT_EQ(check.first->ring_a, 0u);
    EXPECT_EQ(check.first->edge_a, 0u);
    EXPECT_EQ(check.first->edge_b, 2u);
    EXPECT_DOUBLE_EQ(check.first->at.x, 1.0);
    EXPECT_DOUBLE_EQ(check.first->at.y, 1.0);
    EXPECT_EQ(crossing_warning(check, "bowtie.geojson"),
              "bowtie.geojson: the polygon's edges cross at (1.000, 1.000) (outer ring edge 1 and outer ring edge 3); "
              "a point is inside where the rings enclose it an odd number of times (even-odd rule), which may not be "
              "the area meant");
}

TEST(PolygonValidity, AStarInOneStrokeAndAHoleCrossingItsRingAreNamed) {
    // A pentagram in one stroke: every edge crosses the two it does not touch; the sweep names one pair.
    const auto star = find_crossing(parse_wkt_polygon("POLYGON ((0 10, 6 -8, -9.5 3, 9.5 3, -6 -8))"));
    ASSERT_TRUE(star.first);
    const std::size_t apart = star.first->edge_b - star.first->edge_a;
    EXPECT_TRUE(apart == 2 || apart == 3) << star.first->edge_a << ", " << star.first->edge_b;
    // A hole that pokes out of its outer ring, in the second part of a multipolygon.
    const auto hole = find_crossing(parse_wkt_polygon(
        "MULTIPOLYGON (((100 100, 101 100, 101 101, 100 101)), ((0 0, 10 0, 10 10, 0 10), (5 5, 12 5, 12 6, 5 6)))"));
    ASSERT_TRUE(hole.first);
    EXPECT_EQ(hole.first->part, 1u);
    EXPECT_EQ(crossing_warning(hole, "the --polygon WKT"),
              "the --polygon WKT: the polygon's edges cross at (10.000, 5.000) (part 2: outer ring edge 2 and hole 1 "
              "edge 1); a point is inside where the rings enclose it an odd number of times (even-odd rule), which "
              "may not be the area meant");
}

TEST(PolygonValidity, OutlinesThatDoNotCrossAreQuiet) {
    for (const char* wkt : {"POLYGON ((0 0, 10 0, 10 10, 0 10), (2 2, 8 2, 8 8, 2 8))",
                            "POLYGON ((0 0, 2 0, 1 1, 2 2, 0 2, 1 1))",                       // lobes touch at (1, 1)
                            "MULTIPOLYGON (((0 0, 2 0, 2 2, 0 2)), ((1 1, 3 1, 3 3, 1 3)))",  // parts overlap: union
                            "POLYGON ((0 0, 4 0, 4 0, 4 4, 0 4))",                            // a repeated vertex
                            "POLYGON ((0 0, 4 0, 4 4, 2 0, 0 4))"}) {  // a vertex on an edge, no crossing
        const auto check = find_crossing(parse_wkt_polygon(wkt));
        EXPECT_FALSE(check.first) << wkt;
        EXPECT_EQ(crossing_warning(check, "p"), "") << wkt;
    }
}

int side(const XY& a, const XY& b, const XY& c) {
    const double v = (b.x - a.x) * (c.y - a.y) - (b.y - a.y) * (c.x - a.x);
    return (v > 0) - (v < 0);
}

// Whether two edges of the ring cross, every pair tested.
bool brute_force_crossing(std::span<const XY> r) {
    const std::size_t n = r.size();
    for (std::size_t i = 0; i < n; ++i) {
        for (std::size_t j = i + 1; j < n; ++j) {
            const XY a = r[i], b = r[(i + 1) % n], c = r[j], d = r[(j + 1) % n];
            if (side(a, b, c) * side(a, b, d) < 0 && side(c, d, a) * side(c, d, b) < 0) return true;
        }
    }
    return false;
}

TEST(PolygonValidity, TheSweepAgreesWithEveryPairOfEdgesTested) {
    std::mt19937 rng(53);
    int crossing = 0, simple = 0;
    for (int t = 0; t < 22'000; ++t) {
        Ring ring;
        if (t < 20'000) {  // anything on a 7 x 7 grid: touches, collinear edges, repeated vertices
            const int m = 3 + static_cast<int>(rng() % 12);
            for (int k = 0; k < m; ++k) ring.push_back({double(rng() % 7), double(rng() % 7)});
        } else {  // star-shaped (simple) around the origin, radii 1..10, some angles repeated
            const int m = 3 + static_cast<int>(rng() % 40);
            for (int k = 0; k < m; ++k) {
                const double a = 2 * std::numbers::pi * (k + 0.5 * (rng() % 2)) / m, radius = 1 + rng() % 10;
                ring.push_back({radius * std::cos(a), radius * std::sin(a)});
            }
        }
        std::optional<MultiPolygon> p;
        try {
            p.emplace(std::vector<std::vector<Ring>>{{ring}});
        } catch (const Error&) {
            continue;  // fewer than 3 distinct vertices
        }
        const bool expected = brute_force_crossing(p->ring(0));
        (expected ? crossing : simple) += 1;
        ASSERT_EQ(find_crossing(*p).first.has_value(), expected) << "ring #" << t;
    }
    EXPECT_GT(crossing, 10'000);
    EXPECT_GT(simple, 3'000);
}

TEST(PolygonValidity, WorkFollowsTheVerticesWhateverTheShape) {
    constexpr std::size_t n = 100'000;
    for (const double inner : {1000.0, 990.0, 500.0, 1.0}) {  // a circle, a zigzag, stars meeting at the centre
        const MultiPolygon shape({{test::radial_ring(n, [&](std::size_t i) { return i % 2 ? 1000.0 : inner; })}});
        const auto check = find_crossing(shape);
        EXPECT_FALSE(check.first) << inner;
        EXPECT_LT(check.work, 5 * n) << inner << ": 2 events an edge, a few pairs tested each";
    }
    // A zigzag with one vertex moved out past the opposite side: its two edges cross the ring there.
    Ring crossed = test::radial_ring(n, [](std::size_t i) { return i % 2 ? 1000.0 : 990.0; });
    crossed[5000] = {-1.1 * crossed[5000].x, -1.1 * crossed[5000].y};
    const auto check = find_crossing(MultiPolygon({{crossed}}));
    ASSERT_TRUE(check.first);
    EXPECT_TRUE(check.first->edge_a == 4999 || check.first->edge_a == 5000) << check.first->edge_a;
    EXPECT_NEAR(static_cast<double>(check.first->edge_b), 55'000.0, 5.0);
}

}  // namespace
}  // namespace lidarscout
