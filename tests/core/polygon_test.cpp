// MultiPolygon: points inside, outside, on edges and vertices, in holes and in the parts of a
// multipolygon (their union); the indexed test against a brute-force reference on random polygons,
// its work and memory counted; WKT and GeoJSON parsed, and their errors naming what was expected;
// GeoJSON nested 60k deep, or with a field of the wrong kind, one Error (never a crash, never a JSON library's).
#include <gtest/gtest.h>

#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <numbers>
#include <random>
#include <string>
#include <tuple>
#include <utility>
#include <vector>

#include "allocation_counter.hpp"
#include "core/error.hpp"
#include "core/polygon.hpp"
#include "polygon_shapes.hpp"

namespace lidarscout {
namespace {

// The message of the Error parsing `text` ("" when it parses).
std::string error_of(const std::string& text, MultiPolygon (*parse)(std::string_view) = parse_wkt_polygon) {
    try {
        parse(text);
    } catch (const Error& e) {
        return e.what();
    }
    return "";
}

TEST(Polygon, SquareWithHoleEdgesInside) {
    const auto p = parse_wkt_polygon("POLYGON ((0 0, 10 0, 10 10, 0 10, 0 0), (4 4, 6 4, 6 6, 4 6, 4 4))");
    EXPECT_TRUE(p.contains(1, 1));
    EXPECT_TRUE(p.contains(0, 5));    // on an outer edge
    EXPECT_TRUE(p.contains(10, 10));  // a vertex
    EXPECT_TRUE(p.contains(4, 5));    // on the hole's edge
    EXPECT_FALSE(p.contains(5, 5));   // in the hole
    EXPECT_FALSE(p.contains(10.000001, 5));
    EXPECT_FALSE(p.contains(-1, 0));  // on the line of the bottom edge, outside
    EXPECT_FALSE(p.contains(11, 10)); // on the line of the top edge, outside
    EXPECT_DOUBLE_EQ(p.area(), 96.0);
}

TEST(Polygon, MultiPolygonPartsAndATriangle) {
    const auto p = parse_wkt_polygon("multipolygon Z (((0 0 1, 2 0 1, 0 2 1)), ((5 5 0, 7 5 0, 7 7 0, 5 7 0)))");
    EXPECT_TRUE(p.contains(0.5, 0.5));
    EXPECT_TRUE(p.contains(1, 1));  // on the hypotenuse
    EXPECT_FALSE(p.contains(1.01, 1.01));
    EXPECT_TRUE(p.contains(6, 6));
    EXPECT_FALSE(p.contains(3, 3));
    EXPECT_EQ(p.polygon_count(), 2u);
    EXPECT_EQ(p.vertex_count(), 7u);
    EXPECT_DOUBLE_EQ(p.min_x(), 0);
    EXPECT_DOUBLE_EQ(p.max_y(), 7);
}

TEST(Polygon, TouchesBox) {
    const auto p = parse_wkt_polygon("POLYGON ((0 0, 10 0, 0 10), (1 1, 3 1, 1 3))");
    EXPECT_TRUE(p.touches_box(-5, -5, 20, 20));   // the polygon inside the box
    EXPECT_TRUE(p.touches_box(0.5, 0.5, 0.6, 0.6));  // the box inside the polygon
    EXPECT_TRUE(p.touches_box(5, 5, 8, 8));       // a corner on the hypotenuse
    EXPECT_FALSE(p.touches_box(5.1, 5.1, 8, 8));  // within the polygon's box, beyond the hypotenuse
    EXPECT_FALSE(p.touches_box(1.2, 1.2, 1.4, 1.4));  // inside the hole
    EXPECT_TRUE(p.touches_box(-1, 4, 11, 4.5));   // crossing, no vertex inside either
    EXPECT_FALSE(p.touches_box(11, 0, 12, 1));
}

TEST(Polygon, GeoJsonFeatureCollection) {
    const auto p = parse_geojson_polygon(R"({"type": "FeatureCollection", "features": [
        {"type": "Feature", "properties": {}, "geometry": {"type": "Polygon",
         "coordinates": [[[0, 0], [10, 0], [10, 10], [0, 10], [0, 0]], [[4, 4], [6, 4], [6, 6], [4, 6], [4, 4]]]}},
        {"type": "Feature", "geometry": {"type": "MultiPolygon", "coordinates": [[[[20, 0], [30, 0], [30, 10]]]]}}]})");
    EXPECT_TRUE(p.contains(1, 1));
    EXPECT_FALSE(p.contains(5, 5));
    EXPECT_TRUE(p.contains(29, 1));
    EXPECT_FALSE(p.contains(21, 9));
    EXPECT_THROW(parse_geojson_polygon(R"({"type": "Point", "coordinates": [1, 2]})"), Error);
    EXPECT_THROW(parse_geojson_polygon("{not json"), Error);
}

TEST(Polygon, WktErrorsNameWhatWasExpected) {
    EXPECT_NE(error_of("LINESTRING (0 0, 1 1)").find("expected POLYGON or MULTIPOLYGON"), std::string::npos);
    EXPECT_NE(error_of("POLYGON ((0 0, 1 0, 1 1)").find("expected ')' at character 25"), std::string::npos);
    EXPECT_NE(error_of("POLYGON ((0 0, 1 x, 1 1))").find("expected a number"), std::string::npos);
    EXPECT_NE(error_of("POLYGON ((0 0, 1 0, 0 0))").find("at least 3 distinct vertices"), std::string::npos);
    EXPECT_NE(error_of("POLYGON ((0 0, 1 0, 1 1)) junk").find("the end of the text"), std::string::npos);
    EXPECT_EQ(error_of("POLYGON((0 0,1 0,1 1))"), "");
}


using Polygons = std::vector<std::vector<Ring>>;

// The reference test, every edge of every polygon: on an edge (exact cross product), or an odd number
// of a polygon's edges straddling y to the right of the point (the side by the cross product's sign,
// not by the tested code's interpolation); inside the whole when inside any polygon.
bool reference_contains(const Polygons& polygons, double x, double y) {
    for (const auto& rings : polygons) {
        int crossings = 0;
        for (const Ring& r : rings) {
            for (std::size_t i = 0; i < r.size(); ++i) {
                const XY a = r[i], b = r[(i + 1) % r.size()];
                const double cross = (b.x - a.x) * (y - a.y) - (b.y - a.y) * (x - a.x);
                const bool in_box = std::min(a.x, b.x) <= x && x <= std::max(a.x, b.x) &&
                                    std::min(a.y, b.y) <= y && y <= std::max(a.y, b.y);
                if (cross == 0 && in_box) return true;
                if ((a.y > y) != (b.y > y) && (cross > 0) == (b.y > a.y)) ++crossings;
            }
        }
        if (crossings % 2 == 1) return true;
    }
    return false;
}

double orientation(XY a, XY b, XY c) { return (b.x - a.x) * (c.y - a.y) - (b.y - a.y) * (c.x - a.x); }

// Whether closed segments p-q and r-s meet (orientations; exact for the small dyadic coordinates used).
bool segments_meet(XY p, XY q, XY r, XY s) {
    const double o1 = orientation(p, q, r), o2 = orientation(p, q, s), o3 = orientation(r, s, p),
                 o4 = orientation(r, s, q);
    const auto within = [](XY a, XY b, XY c) {  // c, collinear with a-b, lies on it
        return std::min(a.x, b.x) <= c.x && c.x <= std::max(a.x, b.x) && std::min(a.y, b.y) <= c.y &&
               c.y <= std::max(a.y, b.y);
    };
    if (o1 == 0 && within(p, q, r)) return true;
    if (o2 == 0 && within(p, q, s)) return true;
    if (o3 == 0 && within(r, s, p)) return true;
    if (o4 == 0 && within(r, s, q)) return true;
    return (o1 > 0) != (o2 > 0) && o1 != 0 && o2 != 0 && (o3 > 0) != (o4 > 0) && o3 != 0 && o4 != 0;
}

// The reference box test: a corner of the box inside, or an edge with an end in the box or meeting a side.
bool reference_touches(const Polygons& polygons, double x0, double y0, double x1, double y1) {
    if (reference_contains(polygons, x0, y0)) return true;
    const XY c[4] = {{x0, y0}, {x1, y0}, {x1, y1}, {x0, y1}};
    for (const auto& rings : polygons) {
        for (const Ring& r : rings) {
            for (std::size_t i = 0; i < r.size(); ++i) {
                const XY a = r[i], b = r[(i + 1) % r.size()];
                if (a.x >= x0 && a.x <= x1 && a.y >= y0 && a.y <= y1) return true;
                for (int k = 0; k < 4; ++k) {
                    if (segments_meet(a, b, c[k], c[(k + 1) % 4])) return true;
                }
            }
        }
    }
    return false;
}

// 1 to 3 polygons of 1 to 3 rings of 3 to 12 vertices on the integers 0..16 (rings that cross
// themselves and each other, holes outside their polygon, repeated and collinear vertices, many
// horizontal edges: all the degenerate cases at once).
Polygons random_grid_polygons(std::mt19937& rng) {
    std::uniform_int_distribution<int> coordinate(0, 16), count(1, 3), size(3, 12);
    Polygons out(count(rng));
    for (auto& rings : out) {
        rings.resize(count(rng));
        for (Ring& r : rings) {
            r.resize(size(rng));
            for (XY& v : r) v = {double(coordinate(rng)), double(coordinate(rng))};
            if (r.front() == r.back()) r.back().x = r.front().x == 0 ? 1 : 0;
        }
    }
    return out;
}

TEST(Polygon, OverlappingPartsAreTheirUnion) {
    // The issue's case: two overlapping squares from a FeatureCollection (the overlap was a hole).
    const auto squares = parse_geojson_polygon(R"({"type": "FeatureCollection", "features": [
        {"type": "Feature", "geometry": {"type": "Polygon", "coordinates": [[[0, 0], [10, 0], [10, 10], [0, 10]]]}},
        {"type": "Feature", "geometry": {"type": "Polygon", "coordinates": [[[5, 5], [15, 5], [15, 15], [5, 15]]]}}
        ]})");
    EXPECT_TRUE(squares.contains(7, 7));  // in both
    EXPECT_TRUE(squares.contains(2, 2));
    EXPECT_TRUE(squares.contains(12, 12));
    EXPECT_TRUE(squares.contains(10, 7));  // one square's edge inside the other
    EXPECT_FALSE(squares.contains(2, 12));
    EXPECT_DOUBLE_EQ(squares.area(), 200.0);  // the documented sum over parts (their union is 175)
    // Two identical triangles: their inside, not only their edges.
    const auto twins = parse_wkt_polygon("MULTIPOLYGON (((0 0, 10 0, 0 10)), ((0 0, 10 0, 0 10)))");
    EXPECT_TRUE(twins.contains(2, 2));
    EXPECT_TRUE(twins.contains(5, 5));
    EXPECT_FALSE(twins.contains(6, 6));
    // A bow-tie (one ring crossing itself) stays even-odd within its polygon: both lobes inside.
    const auto bow_tie = parse_wkt_polygon("POLYGON ((0 0, 10 10, 10 0, 0 10))");
    EXPECT_TRUE(bow_tie.contains(1, 5));
    EXPECT_TRUE(bow_tie.contains(9, 5));
    EXPECT_FALSE(bow_tie.contains(5, 9));
}

TEST(Polygon, AHoleCutsItsOwnPolygonOnly) {
    // A's hole (4..6) covered by B (3..7): inside. C, an island in D's hole: inside, D's hole around it out.
    const auto p = parse_wkt_polygon("MULTIPOLYGON (((0 0, 10 0, 10 10, 0 10), (4 4, 6 4, 6 6, 4 6)),"
                                     " ((3 3, 7 3, 7 7, 3 7)),"
                                     " ((20 0, 30 0, 30 10, 20 10), (22 2, 28 2, 28 8, 22 8)),"
                                     " ((24 4, 26 4, 26 6, 24 6)))");
    EXPECT_TRUE(p.contains(5, 5));
    EXPECT_TRUE(p.contains(3.5, 5));
    EXPECT_TRUE(p.contains(25, 5));
    EXPECT_FALSE(p.contains(23, 5));
    EXPECT_TRUE(p.contains(22, 5));  // on D's hole's edge
    EXPECT_FALSE(p.contains(15, 5));
    EXPECT_TRUE(p.touches_box(4.5, 4.5, 5.5, 5.5));  // inside B, within A's hole
    EXPECT_FALSE(p.touches_box(22.5, 2.5, 23, 3));   // within D's hole, beside C
    EXPECT_DOUBLE_EQ(p.area(), 96.0 + 16.0 + 64.0 + 4.0);
    // A "hole" larger than its outer ring: that polygon adds nothing, never a negative area.
    EXPECT_DOUBLE_EQ(parse_wkt_polygon("MULTIPOLYGON (((0 0, 1 0, 0 1), (0 0, 10 0, 0 10)), ((20 0, 22 0, 20 2)))")
                         .area(), 2.0);
}

TEST(Polygon, IndexAgreesWithTheReferenceOnDegenerateGridPolygons) {
    // Every half-integer point and box corner: on vertices, on edges (horizontal ones too), on the
    // bands' boundaries (the integers, for most band counts), inside and out.
    std::mt19937 rng(52);
    std::uniform_int_distribution<int> half(-2, 34);
    std::size_t points = 0, inside = 0;
    for (int trial = 0; trial < 400; ++trial) {
        const Polygons polygons = random_grid_polygons(rng);
        const MultiPolygon p(polygons);
        for (int i = -2; i <= 34; ++i) {
            for (int j = -2; j <= 34; ++j) {
                const bool expected = reference_contains(polygons, i / 2.0, j / 2.0);
                ASSERT_EQ(p.contains(i / 2.0, j / 2.0), expected) << "trial " << trial << " at " << i / 2.0 << ", "
                                                                  << j / 2.0;
                ++points, inside += expected;
            }
        }
        for (int k = 0; k < 200; ++k) {
            const double xa = half(rng) / 2.0, xb = half(rng) / 2.0, ya = half(rng) / 2.0, yb = half(rng) / 2.0;
            const double x0 = std::min(xa, xb), x1 = std::max(xa, xb), y0 = std::min(ya, yb), y1 = std::max(ya, yb);
            ASSERT_EQ(p.touches_box(x0, y0, x1, y1), reference_touches(polygons, x0, y0, x1, y1))
                << "trial " << trial << " box " << x0 << ", " << y0 << ", " << x1 << ", " << y1;
        }
    }
    EXPECT_GT(inside, points / 10);  // both answers well represented
    EXPECT_LT(inside, points * 9 / 10);
}

TEST(Polygon, IndexAgreesWithTheReferenceOnRandomBlobsAndStars) {
    std::mt19937 rng(53);
    std::uniform_real_distribution<double> unit(0, 1);
    for (int trial = 0; trial < 40; ++trial) {
        const std::size_t n = 3 + static_cast<std::size_t>(unit(rng) * 3000);
        const double spikes = trial % 2 ? 0.9 : 0.2;  // stars: long edges over many bands; blobs: short ones
        const auto spiky = [&](std::size_t i) { return i % 2 ? 100 * (1 - spikes * unit(rng)) : 100; };
        Polygons polygons{{test::radial_ring(n, spiky)},
                          {test::radial_ring(n / 2 + 3, [&](std::size_t) { return 60 + 10 * unit(rng); }),
                           test::radial_ring(n / 3 + 3, [&](std::size_t) { return 20 + 10 * unit(rng); })}};
        for (XY& v : polygons[1][0]) v.x += 50;  // overlapping the first, its hole partly over it
        for (XY& v : polygons[1][1]) v.x += 50;
        const MultiPolygon p(polygons);
        for (int k = 0; k < 2000; ++k) {
            const double x = -120 + 300 * unit(rng), y = -120 + 240 * unit(rng);
            ASSERT_EQ(p.contains(x, y), reference_contains(polygons, x, y)) << "trial " << trial << " at " << x
                                                                            << ", " << y;
        }
        const XY v = polygons[0][0][n / 2];  // a vertex
        EXPECT_TRUE(p.contains(v.x, v.y));
    }
}

TEST(Polygon, EdgesOnBandBoundariesAndHorizontalEdges) {
    // A 4 x 4 square with a vertex on every integer of its sides, and a comb of horizontal edges:
    // 16 edges over 16 bands of 0.25 with boundaries at every integer; every quarter point checked.
    Ring square;
    for (int i = 0; i < 4; ++i) square.push_back({double(i), 0});
    for (int i = 0; i < 4; ++i) square.push_back({4, double(i)});
    for (int i = 4; i > 0; --i) square.push_back({double(i), 4});
    for (int i = 4; i > 0; --i) square.push_back({0, double(i)});
    const Ring comb = {{10, 0}, {14, 0}, {14, 1}, {11, 1}, {11, 2}, {14, 2}, {14, 3}, {10, 3}, {10, 2}, {10, 1}};
    const Polygons polygons = {{square}, {comb}};
    const MultiPolygon p(polygons);
    for (int i = -4; i <= 64; ++i) {
        for (int j = -4; j <= 20; ++j) {
            ASSERT_EQ(p.contains(i / 4.0, j / 4.0), reference_contains(polygons, i / 4.0, j / 4.0))
                << i / 4.0 << ", " << j / 4.0;
        }
    }
    EXPECT_TRUE(p.contains(12, 1));     // on the comb's inner horizontal edge
    EXPECT_FALSE(p.contains(12, 1.5));  // between its teeth
    EXPECT_TRUE(p.contains(4, 2));      // a vertex on the boundary between bands
    // A ring with no height (all on one line): its edges only.
    const MultiPolygon flat(Polygons{{{{0, 0}, {1, 0}, {2, 0}}}});
    EXPECT_TRUE(flat.contains(0.5, 0));
    EXPECT_FALSE(flat.contains(0.5, 1e-9));
    EXPECT_TRUE(flat.touches_box(1.5, -1, 3, 1));
    EXPECT_FALSE(MultiPolygon().contains(0, 0));
    EXPECT_FALSE(MultiPolygon().touches_box(-1, -1, 1, 1));
}

TEST(Polygon, PointTestWorkFollowsPointsPlusVertices) {
    // 100k vertices around a circle (radii varying by less than the vertices' spacing, as a surveyed
    // outline) and 20k points over its box: the edges examined are a few per point (every edge for
    // every point would be 2 * 10^9). A point examines the edges of its band: about the edges a
    // horizontal line crosses there, plus edges per band.
    std::mt19937 rng(54);
    std::uniform_real_distribution<double> unit(0, 1);
    const std::size_t n = 100'000, points = 20'000;
    const Polygons polygons{{test::radial_ring(n, [&](std::size_t) { return 1000 + 0.05 * unit(rng); })}};
    const MultiPolygon p(polygons);
    std::size_t examined = 0;
    for (std::size_t k = 0; k < points; ++k) {
        const double x = -1000 + 2000 * unit(rng), y = -1000 + 2000 * unit(rng);
        examined += p.edges_examined(x, y);
        if (k % 40 == 0) {
            ASSERT_EQ(p.contains(x, y), reference_contains(polygons, x, y)) << x << ", " << y;
        }
    }
    EXPECT_LE(examined, 10 * points);
    EXPECT_LE(p.index_entries(), 4 * n);
}

TEST(Polygon, LongEdgesKeepTheIndexLinear) {
    // A star of 200k vertices whose spikes reach from radius 1 to 1000: each edge spans about half the
    // height. One list per slab would hold 10^10 entries; the tree lists an edge in its 2 end leaves
    // and at most 12 nodes on average (the leaves made taller when it would hold more).
    const std::size_t n = 200'000;
    Polygons polygons{{test::radial_ring(n, [](std::size_t i) { return i % 2 ? 1.0 : 1000.0; })}};
    const Polygons copy = polygons;
    const test::AllocationCounter counter;
    const MultiPolygon star(std::move(polygons));
    EXPECT_LE(star.index_entries(), 14 * n);
    EXPECT_GE(star.searched_entries(), 10 * n);  // the spikes' edges, sorted in their nodes
    // Vertices 16 bytes, index entries 4 each, leaves 16 bytes (a leaf per 2 vertices), the tree's
    // offsets, and while building: the sorted ys (8 a vertex), each vertex's leaf (4), the lists' offsets.
    EXPECT_LE(counter.bytes(), 160 * n);
    EXPECT_LE(star.held_bytes(), 100 * n);  // what it keeps
    std::mt19937 rng(55);
    std::uniform_real_distribution<double> unit(-1000, 1000);
    for (int k = 0; k < 300; ++k) {
        const double x = unit(rng), y = unit(rng);
        ASSERT_EQ(star.contains(x, y), reference_contains(copy, x, y)) << x << ", " << y;
    }
}

// contains() and the reference at random points of the polygons' box, at points on the y of a vertex
// (the leaves' and nodes' boundaries are vertices' y values) with any x, on vertices, and a rounding
// step beside them: every answer equal. Returns how many were inside.
std::size_t expect_agreement(const Polygons& polygons, std::mt19937& rng, int points, const std::string& name) {
    const MultiPolygon p(polygons);
    const double mx = (p.max_x() - p.min_x()) / 50, my = (p.max_y() - p.min_y()) / 50;
    std::uniform_real_distribution<double> ux(p.min_x() - mx, p.max_x() + mx), uy(p.min_y() - my, p.max_y() + my);
    std::vector<XY> vertices;
    for (const auto& rings : polygons) {
        for (const Ring& r : rings) vertices.insert(vertices.end(), r.begin(), r.end());
    }
    std::uniform_int_distribution<std::size_t> any_vertex(0, vertices.size() - 1);
    std::size_t inside = 0;
    const auto check = [&](double x, double y) {
        const bool expected = reference_contains(polygons, x, y);
        EXPECT_EQ(p.contains(x, y), expected) << name << " at " << x << ", " << y;
        inside += expected;
        return expected == p.contains(x, y);
    };
    for (int k = 0; k < points; ++k) {
        if (!check(ux(rng), uy(rng))) return inside;
        const XY v = vertices[any_vertex(rng)];
        const double beside_x = std::nextafter(v.x, k % 2 ? INFINITY : -INFINITY);
        const double beside_y = std::nextafter(v.y, k % 3 ? INFINITY : -INFINITY);
        if (!check(ux(rng), v.y) || !check(v.x, v.y) || !check(beside_x, v.y) || !check(v.x, beside_y)) return inside;
    }
    return inside;
}

TEST(Polygon, IndexAgreesWithTheReferenceOnStarsZigzagsAndCircles) {
    // Shapes whose horizontal lines cross thousands of edges (sorted and searched in the tree's
    // nodes) and outlines (their edges in the leaves).
    std::mt19937 rng(56);
    std::uniform_real_distribution<double> unit(0, 1);
    const std::size_t n = 10'000;
    const auto radial = [&](auto radius) { return Polygons{{test::radial_ring(n, radius)}}; };
    const std::vector<std::pair<std::string, Polygons>> shapes = {
        {"circle", radial([&](std::size_t) { return 1000 + 0.05 * unit(rng); })},
        {"zigzag", radial([&](std::size_t) { return 1000 + 20 * unit(rng); })},
        {"star 500..1000", radial([](std::size_t i) { return i % 2 ? 500.0 : 1000.0; })},
        {"star 1..1000", radial([](std::size_t i) { return i % 2 ? 1.0 : 1000.0; })},
        {"star of random spikes", radial([&](std::size_t i) { return i % 2 ? 1 + 999 * unit(rng) : 1000; })},
    };
    for (const auto& [name, polygons] : shapes) {
        const MultiPolygon p(polygons);
        if (name != "circle") {
            EXPECT_GT(p.searched_entries(), n) << name;
        }
        const std::size_t inside = expect_agreement(polygons, rng, 1500, name);
        EXPECT_GT(inside, 100u) << name;
    }
}

TEST(Polygon, IndexAgreesWithTheReferenceOnACombOnTheIntegers) {
    // 1000 teeth of heights 300..900 on integer vertices, each tooth's two edges spanning most of the
    // height (sorted lists of ~2000 edges in the nodes): points exactly on the edges (eighths of a
    // tooth, exact in binary), where the search must hand the edge to the direct test, a rounding step
    // beside them, and a grid of half-integer points.
    Ring comb = {{2000, -10}, {0, -10}};
    const auto height = [](int tooth) { return 300.0 + 100 * (tooth % 7); };
    for (int t = 0; t < 1000; ++t) comb.push_back({2.0 * t, 0}), comb.push_back({2.0 * t + 1, height(t)});
    comb.push_back({2000, 0});
    const Polygons polygons{{comb}};
    const MultiPolygon p(polygons);
    EXPECT_GT(p.searched_entries(), 1000u);
    std::mt19937 rng(61);
    std::uniform_int_distribution<int> any_tooth(0, 999), eighth(0, 8);
    for (int k = 0; k < 5000; ++k) {
        const int t = any_tooth(rng);
        const double f = eighth(rng) / 8.0, y = f * height(t), left = 2 * t + f, right = 2 * t + 2 - f;
        ASSERT_TRUE(p.contains(left, y)) << left << ", " << y;  // on the tooth's left edge
        ASSERT_TRUE(p.contains(right, y)) << right << ", " << y;
        for (const double x : {std::nextafter(left, -INFINITY), std::nextafter(right, INFINITY), left + 0.5}) {
            ASSERT_EQ(p.contains(x, y), reference_contains(polygons, x, y)) << x << ", " << y;
        }
    }
    for (int i = -2; i <= 4002; i += 13) {
        for (int j = -22; j <= 1802; j += 7) {
            ASSERT_EQ(p.contains(i / 2.0, j / 2.0), reference_contains(polygons, i / 2.0, j / 2.0))
                << i / 2.0 << ", " << j / 2.0;
        }
    }
}

TEST(Polygon, IndexAgreesWithTheReferenceOnOverlappingStarsAndHoles) {
    // A star with a star-shaped hole; a second star overlapping it (its spikes crossing the first's:
    // two polygons, so two sorted groups in a node); an island in the hole; 40 copies of a small star
    // (a point inside all of them adds 40 odd polygons, past the inline ones).
    std::mt19937 rng(57);
    std::uniform_real_distribution<double> unit(0, 1);
    const auto star = [&](std::size_t n, double inner, double outer, double dx) {
        const auto radius = [&](std::size_t i) { return i % 2 ? inner + (outer - inner) * unit(rng) : outer; };
        Ring r = test::radial_ring(n, radius);
        for (XY& v : r) v.x += dx;
        return r;
    };
    Polygons polygons{{star(4000, 300, 1000, 0), star(2000, 50, 250, 0)},
                      {star(3000, 100, 900, 400)},
                      {star(500, 10, 40, 0)}};
    for (int copy = 0; copy < 40; ++copy) polygons.push_back({star(200, 5, 100, -700)});
    const MultiPolygon p(polygons);
    EXPECT_GT(p.searched_entries(), 4000u);
    expect_agreement(polygons, rng, 1500, "overlapping stars");
    EXPECT_TRUE(p.contains(-700, 0));  // in all 40 copies
}

TEST(Polygon, CrossingEdgesAreTestedOneByOneAndAgree) {
    // Invalid rings, whose edges cross inside the tree's nodes, where no order left to right exists:
    // a star polygon {2001/1000} (each vertex joined to the one nearly opposite: every edge crosses
    // hundreds of others), a bow-tie, and one polygon of two overlapping rings (a "hole" across its
    // outer ring). Their groups fail the check at the nodes' bottom and top and are tested one by one.
    std::mt19937 rng(58);
    const std::size_t n = 2001;
    Ring chords(n);
    for (std::size_t i = 0; i < n; ++i) {
        const double a = 2 * std::numbers::pi * static_cast<double>(i * 1000 % n) / static_cast<double>(n);
        chords[i] = {1000 * std::cos(a), 1000 * std::sin(a)};
    }
    const Polygons crossing{{chords}};
    const MultiPolygon p(crossing);
    // Near the centre, where the chords cross, the line y = 0 crosses every one and they are tested
    // one by one (searched, they would cost a few dozen).
    EXPECT_GT(p.edges_examined(0, 0), 1000u);
    expect_agreement(crossing, rng, 1500, "star polygon {2001/1000}");
    std::uniform_real_distribution<double> unit(0, 1);
    Polygons shifted{{test::radial_ring(3000, [&](std::size_t i) { return i % 2 ? 10 + unit(rng) : 1000; }),
                      test::radial_ring(3000, [&](std::size_t i) { return i % 2 ? 10 + unit(rng) : 900; })}};
    for (XY& v : shifted[0][1]) v.x += 300;  // the second ring overlaps the first, crossing its spikes
    const MultiPolygon overlapping(shifted);
    EXPECT_GT(overlapping.edges_examined(150, 400.5), 1000u);  // where a line crosses ~1900 of their edges
    expect_agreement(shifted, rng, 1000, "overlapping rings of one polygon");
    const Polygons bow_tie{{{{0, 0}, {10, 10}, {10, 0}, {0, 10}}}};
    expect_agreement(bow_tie, rng, 300, "bow-tie");
}

TEST(Polygon, CoordinatesBeyondTheRoundingBoundsAreTestedOneByOne) {
    // A star scaled to 1e120 and to 1e-120 (products that would overflow or underflow the margins):
    // nothing searched, every answer still the reference's. At UTM-like offsets the search holds.
    std::mt19937 rng(59);
    const Ring star = test::radial_ring(4000, [](std::size_t i) { return i % 2 ? 0.3 : 1.0; });
    for (const auto& [name, scale, offset] : {std::tuple{"1e120", 1e120, 0.0}, std::tuple{"1e-120", 1e-120, 0.0},
                                              std::tuple{"1e3 at (5e5, 5e6)", 1e3, 5e5}}) {
        Ring r = star;
        for (XY& v : r) v = {v.x * scale + offset, v.y * scale + 10 * offset};
        const Polygons polygons{{r}};
        const MultiPolygon p(polygons);
        if (offset > 0) {
            EXPECT_GT(p.searched_entries(), 2000u) << name;
        } else {
            EXPECT_EQ(p.searched_entries(), 0u) << name;
        }
        expect_agreement(polygons, rng, 500, name);
    }
}

TEST(Polygon, AStarsPointTestExaminesAHundredEdgesNotTensOfThousands) {
    // Stars of 100k vertices (spikes from radius 500 or 1 to 1000), every horizontal line crossing
    // 24k to 39k of their edges: a point examines its leaf's edges and the binary searches above it.
    std::mt19937 rng(60);
    std::uniform_real_distribution<double> unit(-1000, 1000);
    const std::size_t n = 100'000, points = 5'000;
    for (const double inner : {500.0, 1.0}) {
        const Polygons polygons{{test::radial_ring(n, [&](std::size_t i) { return i % 2 ? inner : 1000.0; })}};
        const MultiPolygon p(polygons);
        std::size_t examined = 0, most = 0;
        for (std::size_t k = 0; k < points; ++k) {
            const double x = unit(rng), y = unit(rng);
            const std::size_t e = p.edges_examined(x, y);
            examined += e, most = std::max(most, e);
            if (k % 50 == 0) {
                ASSERT_EQ(p.contains(x, y), reference_contains(polygons, x, y)) << x << ", " << y;
            }
        }
        EXPECT_LT(examined, 200 * points) << "inner radius " << inner;
        EXPECT_LT(most, 400u) << "inner radius " << inner;
        EXPECT_LE(p.index_entries(), 14 * n);
        EXPECT_LE(p.held_bytes(), 100 * n);
    }
}

std::string geojson_error(const std::string& text) { return error_of(text, parse_geojson_polygon); }

TEST(Polygon, GeoJsonNestedDeepIsOneErrorNotACrash) {
    // A FeatureCollection of FeatureCollections, 60k deep.
    std::string deep;
    for (int i = 0; i < 60'000; ++i) deep += R"({"type": "FeatureCollection", "features": [)";
    for (int i = 0; i < 60'000; ++i) deep += "]}";
    EXPECT_NE(geojson_error(deep).find("polygon: GeoJSON: arrays and objects nested more than the limit of 256 deep"),
              std::string::npos);
    const std::string coordinates = R"({"type": "Polygon", "coordinates": )" + std::string(100'000, '[') +
                                    std::string(100'000, ']') + "}";
    EXPECT_NE(geojson_error(coordinates).find("nested more than"), std::string::npos);
    // Read from a file: the file named.
    const auto file = std::filesystem::temp_directory_path() / ("lidarscout_deep_" + std::to_string(::getpid()) +
                                                                ".geojson");
    std::ofstream(file) << deep;
    try {
        read_polygon_argument(file.string());
        ADD_FAILURE() << "read";
    } catch (const Error& e) {
        EXPECT_EQ(e.file(), file.string());
        EXPECT_NE(e.cause().find("nested more than"), std::string::npos);
    }
    std::filesystem::remove(file);
}

TEST(Polygon, GeoJsonOfTheWrongKindIsNamed) {
    EXPECT_NE(geojson_error(R"({"type": 5, "coordinates": []})").find("GeoJSON: \"type\" is a number, not a string"),
              std::string::npos);
    EXPECT_NE(geojson_error(R"({"type": "FeatureCollection", "features": [{"type": "Feature", "geometry":
              {"type": ["Polygon"]}}]})").find("\"type\" is an array, not a string"), std::string::npos);
    EXPECT_NE(geojson_error(R"({"type": "FeatureCollection", "features": 3})").find("without a features array"),
              std::string::npos);
    EXPECT_NE(geojson_error(R"({"type": "Polygon", "coordinates": [[[0, 0], [1, "a"], [1, 1]]]})")
                  .find("a position is not an array of at least two numbers"),
              std::string::npos);
    const std::string long_type = geojson_error(R"({"type": ")" + std::string(100'000, 'T') + "\"}");
    EXPECT_NE(long_type.find("... (100000 bytes)"), std::string::npos);
    EXPECT_LT(long_type.size(), 400u);
    EXPECT_NE(geojson_error("{\"type\": \"Polygon\", \"coordinates\": [[[0, 0], [1, 0], [1, 1]]]} x").find("not JSON"),
              std::string::npos);
}

}  // namespace
TEST(Polygon, GeoJsonCoordinatesAreKeptAsRingsNotAsADocument) {
    std::string text = R"({"type": "Feature", "properties": {"coordinates": {"any": "thing"}}, "geometry":
                           {"coordinates": [[)";
    constexpr int kVertices = 200'000;
    for (int i = 0; i < kVertices; ++i) {
        const double a = 6.283185307179586 * i / kVertices;
        text += (i ? "," : "") + std::string("[") + std::to_string(1000 * std::cos(a)) + ", " +
                std::to_string(1000 * std::sin(a)) + ", 12.5]";
    }
    text += R"(]], "type": "Polygon"}})";  // (the type after the coordinates)
    const test::AllocationCounter counter;
    const auto p = parse_geojson_polygon(text);
    const std::size_t peak = counter.peak_bytes();
    ASSERT_EQ(p.polygon_count(), 1u);
    EXPECT_EQ(p.vertex_count(), static_cast<std::size_t>(kVertices));
    EXPECT_TRUE(p.contains(0, 0));
    EXPECT_FALSE(p.contains(1001, 0));
    EXPECT_LT(peak, 64u * kVertices) << "a few tens of bytes a vertex (a document would hold ~230), peak " << peak;
}

}  // namespace lidarscout
