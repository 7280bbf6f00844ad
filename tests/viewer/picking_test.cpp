// Picking and measuring: known points placed by hand (the front-most one under the pixel wins,
// chunk points too, nothing far from the pixel), a real survey tile (looking down on its highest
// point picks that point), a filter (what it hides is not picked), the readout in the file's own
// units, and distances between points.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "core/thread_pool.hpp"
#include "dataset/dataset.hpp"
#include "test_data.hpp"
#include "viewer/picking.hpp"
#include "viewer/point_lod.hpp"
#include "viewer/point_sets.hpp"
#include "viewer/survey_tiles.hpp"
#include "viewer/cameras.hpp"

namespace lidarscout::viewer {
namespace {

using test::looking_down;

render::PointAttr attr(float dx, float dy, float dz, std::uint8_t cls, std::uint16_t intensity) {
    render::PointAttr a;
    a.dx = dx, a.dy = dy, a.dz = dz;
    a.classification = cls, a.intensity = intensity;
    return a;
}

// One tile's LOD blocks from `set` (tile index 3) in a snapshot.
SceneSnapshot snapshot_of(const PointSet& set) {
    ThreadPool pool(1);
    SceneSnapshot s;
    s.full_points = build_lod_blocks(set, 3, 80, pool);
    return s;
}

TEST(ViewerPicking, FrontMostPointUnderThePixelWins) {
    PointSet set;
    set.origin_x = 1000, set.origin_y = 2000, set.origin_z = 100;
    set.points = {attr(10, 10, 0, 2, 50), attr(10, 10, 25, 5, 900), attr(40, 40, 3, 6, 7)};
    const auto snapshot = snapshot_of(set);
    const auto camera = looking_down(1010, 2010, 500);
    const auto centre = camera.project(1010, 2010, 125);
    ASSERT_TRUE(centre);
    const auto p = pick_point(snapshot, camera, centre->x, centre->y);
    ASSERT_TRUE(p);
    EXPECT_NEAR(p->x, 1010, 1e-4);
    EXPECT_NEAR(p->y, 2010, 1e-4);
    EXPECT_NEAR(p->z, 125, 1e-4);  // the tree top, not the ground below it
    EXPECT_EQ(p->classification, 5);
    EXPECT_EQ(p->intensity, 900);
    ASSERT_TRUE(p->tile);
    EXPECT_EQ(*p->tile, 3u);
    EXPECT_FALSE(p->chunk_point);
    EXPECT_NEAR(p->depth, 375, 1e-3);

    const auto other = camera.project(1040, 2040, 103);
    ASSERT_TRUE(other);
    const auto q = pick_point(snapshot, camera, other->x + 2, other->y - 1);  // within 4 pixels
    ASSERT_TRUE(q);
    EXPECT_EQ(q->classification, 6);
    EXPECT_NEAR(q->pixel_distance, std::sqrt(5.0), 1e-3);
}

TEST(ViewerPicking, APointFilteredOutIsNotPickedThePointBehindItIs) {
    PointSet set;
    set.origin_x = 1000, set.origin_y = 2000, set.origin_z = 100;
    set.points = {attr(10, 10, 0, 2, 50), attr(10, 10, 25, 5, 900)};  // ground under a tree top
    const auto snapshot = snapshot_of(set);
    const auto camera = looking_down(1010, 2010, 500);
    const auto centre = camera.project(1010, 2010, 125);
    ASSERT_TRUE(centre);
    PickOptions ground;
    ground.filter = PointFilter::parse("2", "", "");
    const auto p = pick_point(snapshot, camera, centre->x, centre->y, ground);
    ASSERT_TRUE(p);
    EXPECT_EQ(p->classification, 2);  // through the hidden tree top, to the ground
    EXPECT_NEAR(p->z, 100, 1e-4);
    PickOptions bright;
    bright.filter = PointFilter::parse("", "", "1000-");
    EXPECT_FALSE(pick_point(snapshot, camera, centre->x, centre->y, bright));  // nothing drawn, nothing picked
}

TEST(ViewerPicking, NothingFarFromThePixelIsPicked) {
    PointSet set;
    set.points = {attr(10, 10, 0, 2, 1)};
    const auto snapshot = snapshot_of(set);
    const auto camera = looking_down(10, 10, 300);
    const auto p = camera.project(10, 10, 0);
    ASSERT_TRUE(p);
    EXPECT_FALSE(pick_point(snapshot, camera, p->x + 10, p->y));
    PickOptions wide;
    wide.radius_px = 12;
    EXPECT_TRUE(pick_point(snapshot, camera, p->x + 10, p->y, wide));
    EXPECT_FALSE(pick_point(SceneSnapshot{}, camera, p->x, p->y));
}

TEST(ViewerPicking, ChunkPointsArePickedWhenAsked) {
    auto set = std::make_shared<PointSet>();
    set->origin_x = 500, set->origin_y = 500;
    set->points = {attr(1, 2, 30, 9, 11)};
    SceneSnapshot snapshot;
    snapshot.chunk_points.push_back(set);
    const auto camera = looking_down(501, 502, 400);
    const auto pixel = camera.project(501, 502, 30);
    ASSERT_TRUE(pixel);
    const auto p = pick_point(snapshot, camera, pixel->x, pixel->y);
    ASSERT_TRUE(p);
    EXPECT_TRUE(p->chunk_point);
    EXPECT_FALSE(p->tile);
    EXPECT_EQ(p->classification, 9);
    PickOptions no_chunks;
    no_chunks.chunk_points = false;
    EXPECT_FALSE(pick_point(snapshot, camera, pixel->x, pixel->y, no_chunks));
}

TEST(ViewerPicking, LookingDownOnARealTilePicksItsHighestPoint) {
    const auto ds = dataset::open_dataset({(test::surveys_dir() / "ky-jmo335-eastern-kentucky").string()});
    const std::uint32_t index = survey::tile_named(ds, "N118E379");
    ThreadPool pool(2);
    const PointSet tile = tile_point_set(ds.tiles[index], ds.las_stride, pool);
    ASSERT_FALSE(tile.points.empty());
    const auto top = *std::max_element(tile.points.begin(), tile.points.end(),
                                       [](const auto& a, const auto& b) { return a.dz < b.dz; });
    SceneSnapshot snapshot;
    snapshot.full_points = build_lod_blocks(tile, index, 80, pool);
    const double x = tile.origin_x + top.dx, y = tile.origin_y + top.dy, z = tile.origin_z + top.dz;
    const auto camera = looking_down(x, y, z + 200);
    const auto pixel = camera.project(x, y, z);
    ASSERT_TRUE(pixel);
    const auto p = pick_point(snapshot, camera, pixel->x, pixel->y);
    ASSERT_TRUE(p);
    EXPECT_NEAR(p->z, z, 1e-3);
    EXPECT_EQ(p->intensity, top.intensity);
    ASSERT_TRUE(p->tile);
    EXPECT_EQ(*p->tile, index);

    // The readout gives the file's own coordinates: the header's scale and offset applied to
    // the record, in its CRS unit (these tiles are in US survey feet).
    const auto readout = point_readout(ds, *p);
    const auto& t = ds.tiles[index];
    EXPECT_NEAR(readout.x * t.xy_to_metres, x, 1e-6);
    EXPECT_NEAR(readout.z * t.z_to_metres, z, 1e-6);
    EXPECT_GE(readout.x, t.tile.header.min[0] - 1e-6);
    EXPECT_LE(readout.x, t.tile.header.max[0] + 1e-6);
    EXPECT_NEAR(readout.z, t.tile.header.max[2], 0.01);
    EXPECT_EQ(readout.file, t.tile.path());
    EXPECT_FALSE(readout.crs.empty());
    EXPECT_NE(readout.horizontal_unit, "metre");
}

TEST(ViewerPicking, TileAtFindsTheTileHoldingAPosition) {
    const auto ds = dataset::open_dataset({(test::surveys_dir() / "ky-jmo335-eastern-kentucky").string()});
    const std::uint32_t index = survey::tile_named(ds, "N118E380");
    const auto& b = ds.tiles[index].bounds_m;
    const auto found = tile_at(ds, b.centre_x(), b.centre_y());
    ASSERT_TRUE(found);
    EXPECT_EQ(*found, index);
    EXPECT_FALSE(tile_at(ds, b.min_x - 1e5, b.min_y));
}

TEST(ViewerPicking, MeasureGivesDistanceHeightDifferenceAndSlope) {
    PickedPoint a, b;
    a.x = 100, a.y = 200, a.z = 50;
    b.x = 103, b.y = 204, b.z = 62;
    const auto m = measure(a, b);
    EXPECT_DOUBLE_EQ(m.horizontal_m, 5);
    EXPECT_DOUBLE_EQ(m.distance_m, 13);
    EXPECT_DOUBLE_EQ(m.dz_m, 12);
    EXPECT_NEAR(m.slope_deg, std::atan2(12.0, 5.0) * 180 / M_PI, 1e-12);
    const auto back = measure(b, a);
    EXPECT_DOUBLE_EQ(back.dz_m, -12);
    EXPECT_DOUBLE_EQ(measure(a, a).slope_deg, 0);
}

TEST(ViewerPicking, MeasureToolTakesTwoPointsThenStartsAgain) {
    PickedPoint a, b, c;
    a.x = 1, b.x = 2, c.x = 3;
    ClickState click;
    click.clicked(a);
    ASSERT_TRUE(click.picked);
    EXPECT_EQ(click.picked->x, 1);
    click.use(ClickTool::Measure);
    EXPECT_FALSE(click.picked);
    click.clicked(a);
    click.clicked(std::nullopt);  // a miss keeps the first point
    EXPECT_TRUE(click.missed);
    ASSERT_TRUE(click.from);
    EXPECT_FALSE(click.to);
    click.clicked(b);
    ASSERT_TRUE(click.to);
    EXPECT_EQ(click.from->x, 1);
    EXPECT_EQ(click.to->x, 2);
    EXPECT_FALSE(click.missed);
    click.clicked(c);  // a third click starts a new measurement
    EXPECT_EQ(click.from->x, 3);
    EXPECT_FALSE(click.to);
}

}  // namespace
}  // namespace lidarscout::viewer
