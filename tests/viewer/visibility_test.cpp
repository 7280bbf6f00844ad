// Visibility: the frustum test of boxes (in front, behind, beside, beyond far), screen
// coverage, visible grid cells, and the full-resolution tile choice (large or few tiles,
// nearest first, within the memory budget).
#include <gtest/gtest.h>

#include "render/point_batch.hpp"
#include "viewer/visibility.hpp"

namespace lidarscout::viewer {
namespace {

constexpr double kX = 300'000.0, kY = 5'000'000.0;

dataset::Bounds box(double x0, double y0, double x1, double y1, double z0 = 0, double z1 = 10) {
    dataset::Bounds b;
    b.min_x = x0, b.min_y = y0, b.min_z = z0, b.max_x = x1, b.max_y = y1, b.max_z = z1;
    return b;
}

// Looking straight down from 1000 m above (kX, kY), 60 degrees field of view, 200 x 100 pixels.
render::Camera top_down() {
    render::Camera c;
    c.x = kX, c.y = kY, c.z = 1000;
    c.pitch_deg = -90;
    c.width = 200, c.height = 100;
    c.near_m = 1, c.far_m = 5000;
    return c;
}

TEST(ViewerVisibility, BoxesInFrontBehindBesideAndBeyondFar) {
    const auto c = top_down();
    EXPECT_TRUE(box_in_view(c, box(kX - 10, kY - 10, kX + 10, kY + 10)));
    // The view is about 2309 m wide (x) and 1155 m tall (y) at the ground.
    EXPECT_FALSE(box_in_view(c, box(kX + 1200, kY - 10, kX + 1300, kY + 10)));
    EXPECT_TRUE(box_in_view(c, box(kX + 1000, kY - 10, kX + 1300, kY + 10)));
    EXPECT_FALSE(box_in_view(c, box(kX - 10, kY + 600, kX + 10, kY + 700)));
    EXPECT_TRUE(box_in_view(c, box(kX - 10, kY + 500, kX + 10, kY + 700)));
    EXPECT_FALSE(box_in_view(c, box(kX - 10, kY - 10, kX + 10, kY + 10, 1500, 2000)));  // above the camera
    EXPECT_FALSE(box_in_view(c, box(kX - 10, kY - 10, kX + 10, kY + 10, -9000, -8000)));  // beyond far
    EXPECT_FALSE(box_in_view(c, dataset::Bounds{}));
}

TEST(ViewerVisibility, ScreenFractionOfABoxOnTheGround) {
    const auto c = top_down();
    // A box of half the view's width and height at the ground (z 0): a quarter of the image.
    const double hw = 0.25 * 2309.4, hh = 0.25 * 1154.7;
    EXPECT_NEAR(screen_fraction(c, box(kX - hw, kY - hh, kX + hw, kY + hh, 0, 0)), 0.25, 0.01);
    EXPECT_NEAR(screen_fraction(c, box(kX - 1e4, kY - 1e4, kX + 1e4, kY + 1e4, 0, 0)), 1.0, 1e-9);
    EXPECT_DOUBLE_EQ(screen_fraction(c, box(kX + 1200, kY, kX + 1300, kY + 1)), 0.0);
    EXPECT_DOUBLE_EQ(screen_fraction(c, box(kX - 1, kY - 1, kX + 1, kY + 1, 0, 2000)), 1.0);  // holds the camera
    EXPECT_DOUBLE_EQ(distance_to(c, box(kX - 1, kY - 1, kX + 1, kY + 1, 0, 10)), 990.0);
}

TEST(ViewerVisibility, VisibleCellsOfTheGrid) {
    const auto c = top_down();
    lidarscout::PatchGrid grid(kX - 640.0 * 10, kY - 640.0 * 10);
    grid.add(kX + 1, kY + 1, 5, {}, 0, 2, 0);        // under the camera
    grid.add(kX + 5000, kY + 1, 5, {}, 0, 2, 0);     // far east
    grid.add(kX - 100, kY + 250, 5, {}, 0, 2, 0);    // near the top edge, in view
    const auto cells = visible_cells(grid, c, 0, 10);
    ASSERT_EQ(cells.size(), 2u);
    EXPECT_EQ(cells[0], grid.cell_of(kX - 100, kY + 250));
    EXPECT_EQ(cells[1], grid.cell_of(kX + 1, kY + 1));
}

dataset::DatasetTile tile(const dataset::Bounds& b, std::uint64_t points) {
    dataset::DatasetTile t;
    t.bounds_m = b;
    t.tile.header.point_count = t.points = points;
    return t;
}

TEST(ViewerVisibility, FullResTilesLargeOrFewNearestFirstWithinBudget) {
    auto c = top_down();
    dataset::Dataset ds;
    ds.tiles.push_back(tile(box(kX + 100, kY - 100, kX + 300, kY + 100), 1000));   // 0: small on screen, right
    ds.tiles.push_back(tile(box(kX - 800, kY - 400, kX + 100, kY + 400), 2000));   // 1: large (27%)
    ds.tiles.push_back(tile(box(kX + 5000, kY, kX + 5100, kY + 100), 1000));       // 2: out of view
    FullResOptions opt;
    opt.memory_budget = 1ull << 30;
    opt.few_tiles = 0;
    auto choice = choose_full_res_tiles(ds, c, opt);
    ASSERT_EQ(choice.tiles, (std::vector<std::uint32_t>{1}));
    EXPECT_EQ(choice.bytes, 2000u * sizeof(render::PointAttr));

    opt.few_tiles = 4;  // two tiles visible: both, nearest first
    c.x = kX + 250;      // tile 0 is right under the camera, tile 1 150 m to the side
    choice = choose_full_res_tiles(ds, c, opt);
    ASSERT_EQ(choice.tiles, (std::vector<std::uint32_t>{0, 1}));

    opt.memory_budget = 1500 * sizeof(render::PointAttr);  // only the nearest fits
    choice = choose_full_res_tiles(ds, c, opt);
    EXPECT_EQ(choice.tiles, (std::vector<std::uint32_t>{0}));
    EXPECT_EQ(choice.wanted, 2u);
    EXPECT_EQ(choice.over_budget, 1u);
}

}  // namespace
}  // namespace lidarscout::viewer
