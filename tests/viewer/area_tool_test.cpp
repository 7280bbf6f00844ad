// The area tool reads the polygon's points as clip does: a 10 x 10 x 2 m "building" (class 6) on flat
// ground (class 2) measures 200 m3 of cut; with a ground filter the building is not measured; a polygon
// of two vertices says why it cannot be measured. On a survey tile in US feet (ky-woodford-county),
// polygons whose vertices are points of the tile and whose edges run along the points' coordinates
// count exactly the points `lidarscout clip --polygon` writes with the WKT the viewer prints for them
// (issue 53: the area tool counted 144,050 where clip wrote 144,048), every vertex point among them.
#include "viewer/area_tool.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <iterator>
#include <numbers>

#include "core/polygon.hpp"
#include "core/thread_pool.hpp"
#include "las_fixture.hpp"
#include "pipelines/clip.hpp"
#include "temp_dir_fixture.hpp"
#include "test_data.hpp"

namespace lidarscout::viewer {
namespace {

class ViewerAreaTool : public test::TempDirTest {};

std::vector<PickedPoint> square(double x0, double y0, double x1, double y1, double z) {
    std::vector<PickedPoint> out(4);
    out[0].x = x0, out[0].y = y0, out[1].x = x1, out[1].y = y0, out[2].x = x1, out[2].y = y1, out[3].x = x0;
    out[3].y = y1;
    for (auto& p : out) p.z = z;
    return out;
}

TEST_F(ViewerAreaTool, MeasuresWhatClipKeeps) {
    std::vector<test::FixturePoint> points;
    for (double y = 0.25; y < 40; y += 0.5) {
        for (double x = 0.25; x < 40; x += 0.5) {
            const bool roof = x > 15 && x < 25 && y > 15 && y < 25;
            points.push_back({960 + x, 1920 + y, roof ? 102.0 : 100.0, static_cast<std::uint8_t>(roof ? 6 : 2)});
        }
    }
    const std::string tile = path("box.las");
    test::write_fixture(tile, points, 32632);
    const auto ds = dataset::open_dataset({tile});
    ThreadPool pool(2);
    const auto polygon = square(970, 1930, 990, 1950, 100);
    const auto all = measure_area(ds, polygon, PointFilter(), pool);
    EXPECT_NEAR(all.horizontal_area_m2, 400, 1e-9);
    EXPECT_NEAR(all.cut_m3, 200, 4.0);  // the cell follows the spacing (1 m): the box's edges fall on cell edges
    EXPECT_NEAR(all.fill_m3, 0, 1e-6);
    EXPECT_EQ(all.points, 1600u);
    const auto ground = measure_area(ds, polygon, PointFilter::parse("2", "", ""), pool);
    EXPECT_EQ(ground.points, 1200u);  // the roof's 400 points are filtered out
    EXPECT_NEAR(ground.cut_m3, 0, 1e-6);  // the hole is filled from the ground around it
    EXPECT_GT(ground.cells_filled, 0u);
    const std::vector<PickedPoint> two(polygon.begin(), polygon.begin() + 2);
    EXPECT_NE(area_line(ds, two, PointFilter(), pool).find("at least 3 vertices"), std::string::npos);
    EXPECT_NE(area_line(ds, polygon, PointFilter(), pool).find("cut 200"), std::string::npos);
}

// World metres of the frame for a coordinate in CRS units, chosen so that area_region (which divides by
// the unit) gives `units` back exactly: a vertex clicked on a point lies on that point. NaN when no
// double does (w / f skips some values).
double world(double units, double f) {
    double w = units * f;
    for (int k = 0; k < 16 && w / f != units; ++k) w = std::nextafter(w, -INFINITY);
    for (int k = 0; k < 32 && w / f != units; ++k) w = std::nextafter(w, INFINITY);
    return w / f == units ? w : NAN;
}

// Whether a vertex can be put exactly on the point `p`.
bool reachable(const std::array<double, 3>& p, double f) { return !std::isnan(world(p[0], f) + world(p[1], f)); }

// `lidarscout clip --polygon` of the WKT the viewer prints for a polygon (viewer_app's polygon_wkt).
std::string wkt_of(const std::vector<PickedPoint>& polygon, double f) {
    std::string wkt = "POLYGON ((";
    char xy[80];
    for (std::size_t k = 0; k <= polygon.size(); ++k) {
        const auto& v = polygon[k % polygon.size()];
        std::snprintf(xy, sizeof xy, "%s%.17g %.17g", k ? ", " : "", v.x / f, v.y / f);
        wkt += xy;
    }
    return wkt + "))";
}

TEST_F(ViewerAreaTool, CountsWhatClipWritesOnASurveyTileInFeet) {
    const auto ds = dataset::open_dataset({(test::surveys_dir() / "ky-woodford-county").string()});
    ASSERT_EQ(ds.tiles.size(), 1u);
    const double f = ds.frame.xy_to_metres;
    ASSERT_NEAR(f, 1200.0 / 3937.0, 1e-12) << "US survey feet: metres and the CRS's units differ";
    const auto stored = test::read_points_back(ds);
    const auto& h = ds.tiles[0].tile.header;
    const double cx = 0.5 * (h.min[0] + h.max[0]), cy = 0.5 * (h.min[1] + h.max[1]);
    const double radius = 0.3 * std::min(h.max[0] - h.min[0], h.max[1] - h.min[1]);
    // 48 vertices, each the point nearest a circle's vertex: a star-shaped polygon with points on its corners.
    std::vector<std::array<double, 3>> corners;  // the points a vertex can be put on exactly
    std::copy_if(stored.begin(), stored.end(), std::back_inserter(corners),
                 [&](const auto& p) { return reachable(p, f); });
    std::vector<PickedPoint> star;
    for (int k = 0; k < 48; ++k) {
        const double a = 2 * std::numbers::pi * k / 48, tx = cx + radius * std::cos(a), ty = cy + radius * std::sin(a);
        const auto nearest = *std::min_element(corners.begin(), corners.end(), [&](const auto& p, const auto& q) {
            const auto d2 = [&](const auto& r) { return (r[0] - tx) * (r[0] - tx) + (r[1] - ty) * (r[1] - ty); };
            return d2(p) < d2(q);
        });
        PickedPoint v;
        v.x = world(nearest[0], f), v.y = world(nearest[1], f), v.z = nearest[2] * f;
        star.push_back(v);
    }
    // A rectangle whose edges run along the coordinates of points (each line holds several of them).
    std::size_t ia = stored.size() / 3, ib = 2 * stored.size() / 3;
    while (!reachable(stored[ia], f)) ++ia;
    while (!reachable(stored[ib], f)) ++ib;
    const auto& a = stored[ia];
    const auto& b = stored[ib];
    auto box = square(world(std::min(a[0], b[0]), f), world(std::min(a[1], b[1]), f), world(std::max(a[0], b[0]), f),
                      world(std::max(a[1], b[1]), f), a[2] * f);
    ThreadPool pool(2);
    for (const auto* polygon : {&star, &box}) {
        const auto measured = measure_area(ds, *polygon, PointFilter(), pool);
        pipelines::ClipRequest request;
        request.output = path("clip.laz");
        request.region = pipelines::polygon_region(parse_wkt_polygon(wkt_of(*polygon, f)));
        const auto clipped = pipelines::clip_to_file(ds, request, pool);
        EXPECT_EQ(measured.points, clipped.points_written);
        const MultiPolygon shape = parse_wkt_polygon(wkt_of(*polygon, f));
        std::uint64_t on_edges = 0;
        for (const auto& p : stored) {
            if (!shape.contains(p[0], p[1])) continue;
            bool on_edge = false;
            for (std::size_t k = 0; k < polygon->size(); ++k) {
                const auto& u = (*polygon)[k];
                const auto& w = (*polygon)[(k + 1) % polygon->size()];
                const double ux = u.x / f, uy = u.y / f, wx = w.x / f, wy = w.y / f;
                on_edge |= (p[0] - ux) * (wy - uy) == (p[1] - uy) * (wx - ux) && p[0] >= std::min(ux, wx) &&
                           p[0] <= std::max(ux, wx) && p[1] >= std::min(uy, wy) && p[1] <= std::max(uy, wy);
            }
            on_edges += on_edge;
        }
        EXPECT_GE(on_edges, polygon == &star ? 48u : 2u) << "points lie on the edges, the vertices among them";
    }
}

}  // namespace
}  // namespace lidarscout::viewer
