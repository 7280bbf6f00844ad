// Scenes: overview points only where a cell has no heightmap, render_scene drawing heightmaps
// under points, elevation colours (the point sets themselves: point_sets_test.cpp).
#include <gtest/gtest.h>

#include <cmath>

#include "dataset/dataset.hpp"
#include "render/framebuffer.hpp"
#include "test_data.hpp"
#include "viewer/point_sets.hpp"
#include "viewer/scene.hpp"

namespace lidarscout::viewer {
namespace {

constexpr double kOx = 700'000.0, kOy = 3'000'000.0;

PatchHeightmap flat(lidarscout::CellKey cell, double x, double y, float z, std::uint32_t colour) {
    PatchHeightmap h;
    h.cell = cell;
    h.origin_x = x, h.origin_y = y;
    h.heights.assign(64 * 64, z);
    h.colours.assign(64 * 64, colour);
    return h;
}

render::Camera above(double x, double y, double z) {
    render::Camera c;
    c.x = x, c.y = y, c.z = z;
    c.pitch_deg = -90;
    c.width = 64, c.height = 48;
    return c;
}

TEST(ViewerScene, OverviewPointsOnlyWhereNoHeightmap) {
    lidarscout::PatchGrid grid(kOx, kOy);
    grid.add(kOx + 10, kOy + 10, 1, {}, 0, 2, 0);
    grid.add(kOx + 11, kOy + 10, 1, {}, 0, 2, 0);
    grid.add(kOx + 700, kOy + 10, 1, {}, 0, 2, 0);
    const std::vector<lidarscout::CellKey> cells{{0, 0}, {1, 0}};
    const std::vector<PatchHeightmap> heightmaps{flat({0, 0}, kOx, kOy, 1, 0)};
    const auto sets = overview_point_sets(grid, cells, heightmaps);
    ASSERT_EQ(sets.size(), 1u);
    EXPECT_DOUBLE_EQ(sets[0].origin_x, kOx + 640.0);
    EXPECT_EQ(point_count(sets), 1u);
}

TEST(ViewerScene, PointsWinOverTheHeightmapTheyLieOn) {
    Scene scene;
    const std::uint32_t green = render::pack_rgba(0, 200, 0), red = render::pack_rgba(250, 0, 0);
    scene.heightmaps.push_back(flat({0, 0}, kOx, kOy, 100.0f, green));
    PointSet points;
    points.origin_x = kOx + 320.0, points.origin_y = kOy + 320.0, points.origin_z = 100.0;
    render::PointAttr p;
    p.r = 250;
    points.points.push_back(p);
    scene.full_points.push_back(points);
    SceneStyle style;
    style.heightmaps.ambient = 1.0f;  // unshaded: the texture's colour itself
    ThreadPool pool(2);
    const auto frame = render_scene(scene, above(kOx + 320.0, kOy + 320.0, 350.0), style, pool);
    EXPECT_EQ(frame.drawn_pixels, 64u * 48u);  // the patch fills the view
    int reds = 0;  // the point projects to the image centre, on a pixel corner
    for (int y = 23; y <= 24; ++y)
        for (int x = 31; x <= 32; ++x) reds += frame.image.at(x, y) == red;
    EXPECT_EQ(reds, 1);
    EXPECT_EQ(frame.image.at(5, 5), green);
    EXPECT_EQ(frame.image.at(60, 40), green);

    const auto empty = render_scene(Scene{}, above(kOx, kOy, 600.0), style, pool);
    EXPECT_EQ(empty.drawn_pixels, 0u);
    EXPECT_EQ(empty.image.at(0, 0), style.resolve.background);
}

TEST(ViewerScene, ElevationColoursSpanTheGivenRange) {
    const auto c = colour_settings(render::ColourMode::Elevation, 200.0, 450.0);
    EXPECT_EQ(c.mode, render::ColourMode::Elevation);
    EXPECT_DOUBLE_EQ(c.z_min, 200.0);
    EXPECT_DOUBLE_EQ(c.z_max, 450.0);
    const auto flat_range = colour_settings(render::ColourMode::Elevation, 10.0, 10.0);
    EXPECT_GT(flat_range.z_max, flat_range.z_min);
}

}  // namespace
}  // namespace lidarscout::viewer
