// Patch heightmaps: the linear method on a grid cell reproduces a plane in metres at the
// patch's place, colours become rgba8, too few chunk points give none, the footprint mask
// clears exactly the texels outside the tiles, and the batch builder keeps the cells' order.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <thread>

#include "core/thread_pool.hpp"
#include "render/framebuffer.hpp"
#include "viewer/heightmap_builder.hpp"
#include "viewer/patch_heightmap.hpp"

namespace lidarscout::viewer {
namespace {

constexpr double kOx = 500'000.0, kOy = 4'200'000.0;  // grid origin, metres

double plane(double x, double y) { return 250.0 + 0.01 * (x - kOx) - 0.02 * (y - kOy); }

// `n` random chunk points with heights on the plane, over [x0, x1) x [y0, y1) (metres from the origin).
void add_points(lidarscout::PatchGrid& grid, int n, double x0, double x1, double y0, double y1, std::uint64_t seed) {
    std::mt19937_64 rng(seed);
    std::uniform_real_distribution<double> ux(x0, x1), uy(y0, y1);
    for (int i = 0; i < n; ++i) {
        const double x = kOx + ux(rng), y = kOy + uy(rng);
        grid.add(x, y, plane(x, y), {200, 100, 50}, 1000, 2, 0);
    }
}

recon::PatchOptions options(std::size_t min_points = kViewerMinPoints, bool rgb = true) {
    return {recon::PatchSpec{}, min_points, rgb};
}

TEST(ViewerPatchHeightmap, LinearReproducesAPlaneAtThePatchPlace) {
    lidarscout::PatchGrid grid(kOx, kOy);
    // Points over the cell (1, 2) and its surroundings, so its whole patch is inside their hull.
    add_points(grid, 600, 640.0 - 200.0, 1280.0 + 200.0, 1280.0 - 200.0, 1920.0 + 200.0, 7);
    const lidarscout::CellKey cell{1, 2};
    const auto h = linear_heightmap(grid, cell, options());
    ASSERT_TRUE(h.has_value());
    EXPECT_EQ(h->cell, cell);
    EXPECT_DOUBLE_EQ(h->origin_x, kOx + 640.0);
    EXPECT_DOUBLE_EQ(h->origin_y, kOy + 1280.0);
    EXPECT_EQ(h->size, 64);
    EXPECT_DOUBLE_EQ(h->texel_m, 10.0);
    ASSERT_EQ(h->heights.size(), 64u * 64u);
    ASSERT_EQ(h->colours.size(), 64u * 64u);
    for (int row = 0; row < 64; row += 7) {
        for (int col = 0; col < 64; col += 5) {
            const double x = h->origin_x + (col + 0.5) * 10.0, y = h->origin_y + (row + 0.5) * 10.0;
            EXPECT_NEAR(h->heights[row * 64 + col], plane(x, y), 0.01) << row << "," << col;
            EXPECT_EQ(h->colours[row * 64 + col], render::pack_rgba(200, 100, 50));
        }
    }
    const auto view = h->view();
    EXPECT_EQ(view.heights.data(), h->heights.data());
    EXPECT_EQ(view.size, 64);
}

TEST(ViewerPatchHeightmap, TooFewPointsGiveNoneAndNoColourGivesNoTexture) {
    lidarscout::PatchGrid grid(kOx, kOy);
    add_points(grid, 8, 0.0, 640.0, 0.0, 640.0, 3);
    EXPECT_FALSE(linear_heightmap(grid, {0, 0}, options(12)).has_value());
    const auto h = linear_heightmap(grid, {0, 0}, options(8, false));
    ASSERT_TRUE(h.has_value());
    EXPECT_TRUE(h->colours.empty());
    EXPECT_FALSE(std::isnan(h->heights.front()));
}

TEST(ViewerPatchHeightmap, MaskClearsTexelsOutsideTheFootprints) {
    lidarscout::PatchGrid grid(kOx, kOy);
    add_points(grid, 200, 0.0, 640.0, 0.0, 640.0, 5);
    auto h = linear_heightmap(grid, {0, 0}, options());
    ASSERT_TRUE(h.has_value());
    dataset::Bounds west;  // the western 300 m of the patch
    west.min_x = kOx - 50.0, west.max_x = kOx + 300.0, west.min_y = kOy - 50.0, west.max_y = kOy + 700.0;
    west.min_z = 0, west.max_z = 1000;
    dataset::Bounds far_away = west;
    far_away.min_x += 1e5, far_away.max_x += 1e5;
    const std::vector<dataset::Bounds> boxes{far_away, west};
    ASSERT_TRUE(mask_to_footprints(*h, boxes));
    for (int row = 0; row < 64; ++row) {
        for (int col = 0; col < 64; ++col) {
            const bool inside = (col + 0.5) * 10.0 <= 300.0;
            EXPECT_EQ(std::isnan(h->heights[row * 64 + col]), !inside) << row << "," << col;
        }
    }
    const std::vector<dataset::Bounds> none{far_away};
    EXPECT_FALSE(mask_to_footprints(*h, none));
}

// Footprints found through their index: among 20,000 small boxes scattered over 40 km (some touching the patch's
// edges) the mask keeps exactly the texels a look at every box keeps, and finds few boxes for the patch.
TEST(ViewerPatchHeightmap, IndexedFootprintsMaskAsALookAtEveryBoxDoes) {
    lidarscout::PatchGrid grid(kOx, kOy);
    add_points(grid, 200, 0.0, 640.0, 0.0, 640.0, 5);
    const auto made = linear_heightmap(grid, {0, 0}, options());
    ASSERT_TRUE(made.has_value());
    std::mt19937 rng(17);
    std::uniform_real_distribution<double> at(-2e4, 2e4), side(5.0, 120.0);
    std::vector<dataset::Bounds> boxes;
    for (int k = 0; k < 20'000; ++k) {
        dataset::Bounds b;
        const auto place = [&] { return k < 40 ? at(rng) / 40.0 + 320.0 : at(rng); };  // (the first 40 about it)
        b.min_x = kOx + place();
        b.min_y = kOy + place();
        b.max_x = b.min_x + side(rng), b.max_y = b.min_y + side(rng), b.min_z = 0, b.max_z = 10;
        boxes.push_back(b);
    }
    dataset::Bounds edge;  // touching the patch's east edge only
    edge.min_x = kOx + 640.0, edge.max_x = kOx + 700.0, edge.min_y = kOy, edge.max_y = kOy + 640.0;
    edge.min_z = 0, edge.max_z = 10;
    boxes.push_back(edge);
    const Footprints footprints(boxes);
    const auto near = footprints.overlapping(kOx, kOy, kOx + 640.0, kOy + 640.0);
    EXPECT_LT(near.size(), 200u);
    EXPECT_NE(std::find_if(near.begin(), near.end(), [&](const auto& b) { return b.min_x == edge.min_x; }),
              near.end()) << "a box touching the patch is near it";
    std::vector<std::size_t> found(4);  // (threads at once: a heightmap builder's, a server's requests)
    std::vector<std::thread> threads;
    for (std::size_t k = 0; k < found.size(); ++k) {
        threads.emplace_back([&, k] {
            for (int i = 0; i < 50; ++i) found[k] = footprints.overlapping(kOx, kOy, kOx + 640.0, kOy + 640.0).size();
        });
    }
    for (auto& t : threads) t.join();
    EXPECT_EQ(found, std::vector<std::size_t>(4, near.size()));
    auto h = *made;
    const bool any = mask_to_footprints(h, footprints);
    std::size_t kept = 0;
    for (int row = 0; row < 64; ++row) {
        for (int col = 0; col < 64; ++col) {
            const double x = kOx + (col + 0.5) * 10.0, y = kOy + (row + 0.5) * 10.0;
            const bool inside = std::any_of(boxes.begin(), boxes.end(), [&](const dataset::Bounds& b) {
                return x >= b.min_x && x <= b.max_x && y >= b.min_y && y <= b.max_y;
            });
            EXPECT_EQ(std::isnan(h.heights[row * 64 + col]), !inside) << row << "," << col;
            kept += inside;
        }
    }
    EXPECT_GT(kept, 0u);
    EXPECT_EQ(any, kept > 0);
}

TEST(ViewerHeightmapBuilder, LinearBuildKeepsOrderAndSkipsSparseOrMaskedCells) {
    lidarscout::PatchGrid grid(kOx, kOy);
    add_points(grid, 300, 0.0, 1280.0, 0.0, 640.0, 11);  // cells (0,0) and (1,0)
    grid.add(kOx + 5000.0, kOy + 5000.0, 100.0, {}, 0, 2, 0);  // a lone point in cell (7,7)
    HeightmapBuildOptions opt;
    opt.patch = options();
    std::size_t progressed = 0;
    opt.progress = [&](std::size_t n) { progressed += n; };
    ThreadPool pool(2);
    const std::vector<lidarscout::CellKey> cells{{1, 0}, {7, 7}, {0, 0}};
    const auto built = build_linear_heightmaps(grid, cells, opt, pool);
    ASSERT_EQ(built.size(), 2u);
    EXPECT_EQ(built[0].cell, (lidarscout::CellKey{1, 0}));
    EXPECT_EQ(built[1].cell, (lidarscout::CellKey{0, 0}));
    EXPECT_EQ(progressed, 3u);

    dataset::Bounds west;  // only cell (0, 0)
    west.min_x = kOx, west.max_x = kOx + 600.0, west.min_y = kOy, west.max_y = kOy + 640.0;
    opt.footprints = {west};
    const auto masked = build_linear_heightmaps(grid, cells, opt, pool);
    ASSERT_EQ(masked.size(), 1u);
    EXPECT_EQ(masked[0].cell, (lidarscout::CellKey{0, 0}));
}

TEST(ViewerHeightmapBuilder, ColourIsDetectedFromTheChunkPoints) {
    lidarscout::PatchGrid grid(kOx, kOy);
    grid.add(kOx + 1, kOy + 1, 0, {}, 0, 2, 0);
    EXPECT_FALSE(chunk_points_have_rgb(grid));
    grid.add(kOx + 2, kOy + 1, 0, {10, 0, 0}, 0, 2, 0);
    EXPECT_TRUE(chunk_points_have_rgb(grid));
}

}  // namespace
}  // namespace lidarscout::viewer
