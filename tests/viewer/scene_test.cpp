// Scenes: chunk points as point sets (cell corner origin), overview points only where a cell
// has no heightmap, render_scene drawing heightmaps under points, and a real tile decoded at
// full resolution (every point, inside its bounds, in metres).
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

PatchHeightmap flat(dataset::CellKey cell, double x, double y, float z, std::uint32_t colour) {
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

TEST(ViewerScene, CellPointSetsAreRelativeToTheCellCorner) {
    dataset::PatchGrid grid(kOx, kOy);
    grid.add(kOx + 650.0, kOy + 10.0, 123.5, {1, 2, 3}, 77, 6, 0);
    const auto set = cell_point_set(grid, {1, 0});
    EXPECT_DOUBLE_EQ(set.origin_x, kOx + 640.0);
    EXPECT_DOUBLE_EQ(set.origin_y, kOy);
    ASSERT_EQ(set.points.size(), 1u);
    EXPECT_NEAR(set.points[0].dx, 10.0f, 1e-3);
    EXPECT_NEAR(set.points[0].dy, 10.0f, 1e-3);
    EXPECT_NEAR(set.origin_z + set.points[0].dz, 123.5, 1e-3);
    EXPECT_EQ(set.points[0].r, 1);
    EXPECT_EQ(set.points[0].intensity, 77);
    EXPECT_EQ(set.points[0].classification, 6);
    const auto batches = batches_of(std::span(&set, 1));
    ASSERT_EQ(batches.size(), 1u);
    EXPECT_EQ(batches[0].points.size(), 1u);
}

TEST(ViewerScene, OverviewPointsOnlyWhereNoHeightmap) {
    dataset::PatchGrid grid(kOx, kOy);
    grid.add(kOx + 10, kOy + 10, 1, {}, 0, 2, 0);
    grid.add(kOx + 11, kOy + 10, 1, {}, 0, 2, 0);
    grid.add(kOx + 700, kOy + 10, 1, {}, 0, 2, 0);
    const std::vector<dataset::CellKey> cells{{0, 0}, {1, 0}};
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

TEST(ViewerScene, RealTileDecodedAtFullResolution) {
    const auto ds = dataset::open_dataset({(test::surveys_dir() / "ky-woodford-county").string()});
    ASSERT_EQ(ds.tiles.size(), 1u);
    const auto& t = ds.tiles[0];
    ThreadPool pool(2);
    std::uint64_t progressed = 0;
    const auto set = tile_point_set(t, ds.las_stride, pool, [&](std::uint64_t n) { progressed += n; });
    ASSERT_EQ(set.points.size(), t.tile.header.point_count);
    EXPECT_EQ(progressed, t.tile.header.point_count);
    EXPECT_EQ(tile_point_set_bytes(t), t.tile.header.point_count * sizeof(render::PointAttr));
    const auto& b = t.bounds_m;
    std::size_t outside = 0, coloured = 0;
    for (const auto& p : set.points) {
        const double x = set.origin_x + p.dx, y = set.origin_y + p.dy, z = set.origin_z + p.dz;
        outside += x < b.min_x - 0.01 || x > b.max_x + 0.01 || y < b.min_y - 0.01 || y > b.max_y + 0.01 ||
                   z < b.min_z - 0.01 || z > b.max_z + 0.01;
        coloured += (p.r | p.g | p.b) != 0;
    }
    EXPECT_EQ(outside, 0u);
    EXPECT_GT(coloured, set.points.size() / 2);  // the Kentucky tiles carry RGB
}

}  // namespace
}  // namespace lidarscout::viewer
