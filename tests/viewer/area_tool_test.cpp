// The area tool on what a snapshot holds: a 10 x 10 x 2 m "building" (class 6) on flat ground
// (class 2) held as LOD blocks measures 200 m3 of cut; with a ground filter the building is not
// drawn, so it is not measured either; a polygon of two vertices says why it cannot be measured.
#include "viewer/area_tool.hpp"

#include <gtest/gtest.h>

#include "core/thread_pool.hpp"
#include "viewer/point_lod.hpp"

namespace lidarscout::viewer {
namespace {

SceneSnapshot box_on_ground() {
    PointSet set;
    set.origin_x = 960, set.origin_y = 1920, set.origin_z = 100;
    for (double y = 0.25; y < 40; y += 0.5) {
        for (double x = 0.25; x < 40; x += 0.5) {
            render::PointAttr a;
            a.dx = static_cast<float>(x), a.dy = static_cast<float>(y);
            const bool roof = x > 15 && x < 25 && y > 15 && y < 25;
            a.dz = roof ? 2.0f : 0.0f;
            a.classification = roof ? 6 : 2;
            set.points.push_back(a);
        }
    }
    ThreadPool pool(1);
    SceneSnapshot s;
    s.full_points = build_lod_blocks(set, 0, 80, pool);
    return s;
}

std::vector<PickedPoint> square(double x0, double y0, double x1, double y1, double z) {
    std::vector<PickedPoint> out(4);
    out[0].x = x0, out[0].y = y0, out[1].x = x1, out[1].y = y0, out[2].x = x1, out[2].y = y1, out[3].x = x0;
    out[3].y = y1;
    for (auto& p : out) p.z = z;
    return out;
}

TEST(ViewerAreaTool, MeasuresWhatIsDrawn) {
    const auto snapshot = box_on_ground();
    const auto polygon = square(970, 1930, 990, 1950, 100);
    const auto all = measure_area(snapshot, polygon, PointFilter());
    EXPECT_NEAR(all.horizontal_area_m2, 400, 1e-9);
    EXPECT_NEAR(all.cut_m3, 200, 4.0);  // the cell follows the spacing (1 m): the box's edges fall on cell edges
    EXPECT_NEAR(all.fill_m3, 0, 1e-6);
    EXPECT_EQ(all.points, 1600u);
    const auto ground = measure_area(snapshot, polygon, PointFilter::parse("2", "", ""));
    EXPECT_EQ(ground.points, 1200u);  // the roof's 400 points are not drawn
    EXPECT_NEAR(ground.cut_m3, 0, 1e-6);  // the hole is filled from the ground around it
    EXPECT_GT(ground.cells_filled, 0u);
    const std::vector<PickedPoint> two(polygon.begin(), polygon.begin() + 2);
    EXPECT_NE(area_line(snapshot, two, PointFilter()).find("at least 3 vertices"), std::string::npos);
    EXPECT_NE(area_line(snapshot, polygon, PointFilter()).find("cut 200"), std::string::npos);
}

}  // namespace
}  // namespace lidarscout::viewer
