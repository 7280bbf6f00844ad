// ChunkPointLoader: every chunk point of the surveys lands in the grid exactly once, equal to
// what read_chunk_points gives (placed in the dataset's frame, metres); both back ends agree; a focus change mid-run is
// followed; cancel stops early without hanging.
#include <gtest/gtest.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <mutex>
#include <tuple>

#include "dataset/chunk_point_loader.hpp"
#include "dataset/chunk_points.hpp"
#include "dataset/dataset.hpp"
#include "core/patch_grid.hpp"
#include "io/file.hpp"
#include "test_data.hpp"

namespace lidarscout::dataset {
namespace {

using Key = std::tuple<std::uint32_t, double, double, double>;  // tile, x, y, z in metres

Key key(std::uint32_t tile, double x, double y, double z) { return {tile, x, y, z}; }

// Same points (sorted) within the grid's storage precision: float offsets inside a 640 m
// cell (< 0.1 mm) and float heights.
void expect_same_points(const std::vector<Key>& got, const std::vector<Key>& expected) {
    ASSERT_EQ(got.size(), expected.size());
    for (std::size_t i = 0; i < got.size(); ++i) {
        ASSERT_EQ(std::get<0>(got[i]), std::get<0>(expected[i])) << i;
        ASSERT_NEAR(std::get<1>(got[i]), std::get<1>(expected[i]), 1e-3) << i;
        ASSERT_NEAR(std::get<2>(got[i]), std::get<2>(expected[i]), 1e-3) << i;
        ASSERT_NEAR(std::get<3>(got[i]), std::get<3>(expected[i]), 1e-3) << i;
    }
}

const Dataset& surveys() {
    static const Dataset ds = open_dataset({test::surveys_dir().string()});
    return ds;
}

std::vector<Key> grid_keys(const PatchGrid& grid) {
    std::vector<Key> out;
    for (const auto cell : grid.cells()) {
        for (const auto& p : grid.points_in(cell)) {
            const auto a = grid.to_absolute(cell, p);
            out.push_back(key(a.tile, a.x, a.y, a.z));
        }
    }
    std::sort(out.begin(), out.end());
    return out;
}

std::vector<Key> expected_keys(const Dataset& ds) {
    std::vector<Key> out;
    for (std::uint32_t i = 0; i < ds.tiles.size(); ++i) {
        const auto& t = ds.tiles[i];
        for (const auto& cp : read_chunk_points(io::File::open(t.tile.path()), t.tile)) {
            double x = cp.point.x, y = cp.point.y, z = cp.point.z;
            t.place(x, y, z);  // metres of the dataset's frame (the surveys mix CRSs: most are reprojected)
            out.push_back(key(i, x, y, z));
        }
    }
    std::sort(out.begin(), out.end());
    return out;
}

std::unique_ptr<PatchGrid> make_grid(const Dataset& ds) {
    const auto [ox, oy] = patch_grid_origin(ds);
    return std::make_unique<PatchGrid>(ox, oy);
}

// One reader thread, one read at a time: tiles complete in the order they are handed out.
ChunkPointLoaderOptions one_read_at_a_time() {
    ChunkPointLoaderOptions opt;
    opt.reads.backend = io::ReadBackend::Pread;
    opt.reads.threads = 1;
    opt.reads.queue_depth = 1;
    return opt;
}

class Loader : public ::testing::TestWithParam<io::ReadBackend> {};

TEST_P(Loader, LoadsEveryChunkPointOfTheSurveys) {
    if (GetParam() == io::ReadBackend::IoUring && !io::io_uring_available()) GTEST_SKIP() << "no io_uring here";
    const Dataset& ds = surveys();
    ASSERT_TRUE(ds.skipped.empty());
    auto grid = make_grid(ds);
    ChunkPointLoaderOptions opt;
    opt.reads.backend = GetParam();
    std::atomic<std::size_t> done_callbacks{0};
    ChunkPointLoader loader(ds, *grid, opt);
    loader.on_tile_done([&](std::span<const std::uint32_t> tiles, std::span<const CellKey>) {
        done_callbacks += tiles.size();
    });
    loader.start();
    loader.wait();
    EXPECT_EQ(loader.backend(), GetParam());
    EXPECT_TRUE(loader.errors().empty()) << loader.errors().front().message();
    EXPECT_EQ(loader.failed(), 0u);
    EXPECT_EQ(loader.loaded(), ds.chunk_point_count);
    EXPECT_EQ(loader.total(), ds.chunk_point_count);
    EXPECT_EQ(grid->size(), ds.chunk_point_count);
    EXPECT_EQ(done_callbacks.load(), ds.tiles.size());
    expect_same_points(grid_keys(*grid), expected_keys(ds));
}

INSTANTIATE_TEST_SUITE_P(Backends, Loader, ::testing::Values(io::ReadBackend::Pread, io::ReadBackend::IoUring),
                         [](const auto& info) { return std::string(io::backend_name(info.param)); });

TEST(LoaderColour, SixteenBitColourIsScaledPerTile) {
    const Dataset ds = open_dataset({(test::surveys_dir() / "ky-woodford-county").string()});
    auto grid = make_grid(ds);
    ChunkPointLoader loader(ds, *grid);
    loader.start();
    loader.wait();
    // Reference: the high byte of each 16-bit channel (this Kentucky survey has 16-bit colour).
    std::vector<std::tuple<long long, long long, int, int, int>> expected, got;
    for (const auto& t : ds.tiles) {
        for (const auto& cp : read_chunk_points(io::File::open(t.tile.path()), t.tile)) {
            expected.emplace_back(std::llround(cp.point.x * t.xy_to_metres * 1000),
                                  std::llround(cp.point.y * t.xy_to_metres * 1000), cp.point.rgb[0] >> 8,
                                  cp.point.rgb[1] >> 8, cp.point.rgb[2] >> 8);
        }
    }
    for (const auto cell : grid->cells()) {
        for (const auto& p : grid->points_in(cell)) {
            const auto a = grid->to_absolute(cell, p);
            got.emplace_back(std::llround(a.x * 1000), std::llround(a.y * 1000), a.rgb.r, a.rgb.g, a.rgb.b);
        }
    }
    std::sort(expected.begin(), expected.end());
    std::sort(got.begin(), got.end());
    EXPECT_EQ(got, expected);
    ASSERT_FALSE(got.empty());
    EXPECT_TRUE(std::any_of(got.begin(), got.end(), [](const auto& t) { return std::get<2>(t) > 16; }));
}

// With one reader thread taking one read at a time, tiles complete in exactly the order the
// loader hands them out: after the focus moves, every following tile is the nearest one left.
TEST(LoaderPriority, FollowsAFocusChangeMidRun) {
    const Dataset& ds = surveys();
    ASSERT_GT(ds.tiles.size(), 50u);
    const auto& far = ds.tiles.back().bounds_m;  // the last tile in file order (Raleigh)
    const auto& near = ds.tiles.front().bounds_m;
    auto grid = make_grid(ds);
    ChunkPointLoader loader(ds, *grid, one_read_at_a_time());
    std::mutex mutex;
    std::vector<std::uint32_t> order;
    constexpr std::size_t kSwitchAfter = 5;
    loader.set_focus(near.centre_x(), near.centre_y());
    loader.on_tile_done([&](std::span<const std::uint32_t> tiles, std::span<const CellKey>) {
        std::lock_guard lock(mutex);
        ASSERT_EQ(tiles.size(), 1u) << "a tile read is told alone";
        order.push_back(tiles[0]);
        if (order.size() == kSwitchAfter) loader.set_focus(far.centre_x(), far.centre_y());
    });
    loader.start();
    loader.wait();
    ASSERT_EQ(order.size(), ds.tiles.size());
    // Before the switch: nearest to the first focus first.
    for (std::size_t i = 1; i < kSwitchAfter; ++i) {
        EXPECT_LE(ds.tiles[order[i - 1]].bounds_m.distance_xy(near.centre_x(), near.centre_y()),
                  ds.tiles[order[i]].bounds_m.distance_xy(near.centre_x(), near.centre_y()));
    }
    // After it (the tile in progress at the switch may finish first): nearest to the new focus.
    const std::size_t from = kSwitchAfter + 1;
    EXPECT_EQ(ds.tiles[order[from]].bounds_m.distance_xy(far.centre_x(), far.centre_y()), 0.0);
    for (std::size_t i = from + 1; i < order.size(); ++i) {
        EXPECT_LE(ds.tiles[order[i - 1]].bounds_m.distance_xy(far.centre_x(), far.centre_y()),
                  ds.tiles[order[i]].bounds_m.distance_xy(far.centre_x(), far.centre_y()))
            << "position " << i;
    }
    // The first tile after the switch is in the far region, not near the first focus.
    EXPECT_GT(ds.tiles[order[from]].bounds_m.distance_xy(near.centre_x(), near.centre_y()), 100'000.0);
}

TEST(LoaderCancel, StopsEarlyAndKeepsWhatWasLoaded) {
    const Dataset& ds = surveys();
    auto grid = make_grid(ds);
    ChunkPointLoader loader(ds, *grid, one_read_at_a_time());
    loader.on_tile_done([&](std::span<const std::uint32_t>, std::span<const CellKey>) {
        if (loader.tiles_done() == 3) loader.cancel();
    });
    loader.start();
    loader.wait();
    EXPECT_TRUE(loader.finished());
    EXPECT_LE(loader.tiles_done(), 4u);
    EXPECT_LT(loader.loaded(), ds.chunk_point_count);
    EXPECT_EQ(grid->size(), loader.loaded());
}

TEST(LoaderErrors, VanishedFileIsReportedAndOthersLoad) {
    Dataset ds = open_dataset({(test::surveys_dir() / "ky-jmo335-eastern-kentucky").string()});
    ASSERT_GT(ds.tiles.size(), 2u);
    auto gone = std::make_shared<TileFile>(*ds.tiles[1].tile.file);
    gone->path = "/nonexistent/gone.laz";  // as if deleted after the scan
    ds.tiles[1].tile.file = gone;
    auto grid = make_grid(ds);
    ChunkPointLoader loader(ds, *grid);
    loader.start();
    loader.wait();
    ASSERT_EQ(loader.errors().size(), 1u);
    EXPECT_NE(loader.errors()[0].file.find("gone.laz"), std::string::npos);
    EXPECT_NE(loader.errors()[0].cause.find("cannot open"), std::string::npos);
    EXPECT_EQ(loader.loaded() + loader.failed(), ds.chunk_point_count);
    EXPECT_EQ(loader.failed(), ds.tiles[1].chunk_points);
}

}  // namespace
}  // namespace lidarscout::dataset
