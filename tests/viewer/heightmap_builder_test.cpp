// The heightmap stage over many patches: the tiles' footprints, and linear heightmaps exact on a
// plane at every texel, none for a window with too few chunk points, masked texel by texel
// outside the footprints (the cells' order and colour detection: patch_heightmap_test.cpp).
#include "viewer/heightmap_builder.hpp"

#include <gtest/gtest.h>

#include <cmath>

#include "core/thread_pool.hpp"
#include "dataset/dataset.hpp"
#include "test_data.hpp"

namespace lidarscout::viewer {
namespace {

constexpr double kOx = 600'000.0, kOy = 4'100'000.0;

double plane(double x, double y) { return 300 + 0.01 * (x - kOx) + 0.02 * (y - kOy); }

// Chunk points every 40 m over cells (0, 0) to (2, 2) on the plane, and 3 stray points in (5, 5).
void fill(lidarscout::PatchGrid& grid, lidarscout::Rgb8 colour) {
    for (double x = kOx + 5; x < kOx + 3 * 640; x += 40) {
        for (double y = kOy + 5; y < kOy + 3 * 640; y += 40) grid.add(x, y, plane(x, y), colour, 0, 2, 0);
    }
    for (int i = 0; i < 3; ++i) grid.add(kOx + 5 * 640 + 100 + i * 50, kOy + 5 * 640 + 100, 10, colour, 0, 2, 0);
}

TEST(ViewerHeightmapBuilder, FootprintsAreTheTilesHeaderBounds) {
    const auto ds = dataset::open_dataset({(test::surveys_dir() / "ky-jmo335-eastern-kentucky").string()});
    const auto footprints = tile_footprints(ds);
    ASSERT_EQ(footprints.size(), ds.tiles.size());
    for (std::size_t i = 0; i < footprints.size(); ++i) {
        EXPECT_EQ(footprints[i].min_x, ds.tiles[i].bounds_m.min_x);
        EXPECT_EQ(footprints[i].max_y, ds.tiles[i].bounds_m.max_y);
    }
}

TEST(ViewerHeightmapBuilder, LinearHeightmapsAreExactOnAPlaneAndMaskedTexelByTexel) {
    lidarscout::PatchGrid grid(kOx, kOy);
    fill(grid, {90, 120, 60});
    ThreadPool pool(2);
    HeightmapBuildOptions options;
    const std::vector<lidarscout::CellKey> cells = {{1, 1}, {5, 5}};
    const auto maps = build_linear_heightmaps(grid, cells, options, pool);
    ASSERT_EQ(maps.size(), 1u);  // (5, 5) has 3 chunk points: no heightmap
    const auto& h = maps[0];
    EXPECT_EQ(h.cell, (lidarscout::CellKey{1, 1}));
    for (int row = 0; row < h.size; row += 7) {
        for (int col = 0; col < h.size; col += 7) {
            const double x = h.origin_x + (col + 0.5) * h.texel_m, y = h.origin_y + (row + 0.5) * h.texel_m;
            const float v = h.heights[static_cast<std::size_t>(row) * h.size + col];
            EXPECT_NEAR(v, plane(x, y), 1e-3) << col << ", " << row;
        }
    }
    dataset::Bounds west;  // only the western half of cell (1, 1) holds data
    west.min_x = kOx, west.max_x = kOx + 640 + 320, west.min_y = kOy, west.max_y = kOy + 3 * 640;
    options.footprints = {west};
    const auto masked = build_linear_heightmaps(grid, cells, options, pool);
    ASSERT_EQ(masked.size(), 1u);
    EXPECT_FALSE(std::isnan(masked[0].heights[10 * 64 + 10]));
    EXPECT_TRUE(std::isnan(masked[0].heights[10 * 64 + 50]));
}

}  // namespace
}  // namespace lidarscout::viewer
