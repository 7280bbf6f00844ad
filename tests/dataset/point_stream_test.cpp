// for_each_metric_batch across tiles: every point of every tile once, in the tiles' order and in
// file order, tile_done right after a tile's last batch, the same points as a tile streamed
// alone; colour only when asked; a tile that vanished after opening is named in the error; with a
// skip callback a corrupt chunk costs its points only and is reported once.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <filesystem>
#include <numeric>
#include <vector>

#include "core/error.hpp"
#include "core/thread_pool.hpp"
#include "dataset/dataset.hpp"
#include "dataset/point_stream.hpp"
#include "damaged_tile.hpp"
#include "temp_dir_fixture.hpp"
#include "test_data.hpp"

namespace lidarscout {
namespace {

namespace fs = std::filesystem;

const dataset::Dataset& isprs() {
    static const auto ds = dataset::open_dataset({(test::surveys_dir() / "isprs-filter-test-sites").string()});
    return ds;
}

// What a stream delivered, in the order it came.
struct Event {
    std::uint32_t tile = 0;
    std::uint64_t first = 0, count = 0;
    bool done = false;  // a tile_done call
};

// Order-sensitive digest of points (coordinates to the millimetre, class, intensity).
std::uint64_t digest(std::uint64_t h, std::span<const dataset::MetricPoint> points) {
    for (const auto& p : points) {
        for (const double v : {p.x, p.y, p.z}) h = h * 1000003u + static_cast<std::uint64_t>(std::llround(v * 1000));
        h = h * 31u + p.classification;
        h = h * 31u + p.intensity;
    }
    return h;
}

TEST(PointStream, TilesComeInTheGivenOrderEachWholeThenItsTileDone) {
    const auto& ds = isprs();
    ASSERT_GE(ds.tiles.size(), 4u);
    std::vector<std::uint32_t> order(ds.tiles.size());
    std::iota(order.rbegin(), order.rend(), 0u);  // last tile first
    ThreadPool pool(2);
    std::vector<Event> events;
    std::vector<std::uint64_t> digests(ds.tiles.size(), 0);
    dataset::for_each_metric_batch(
        ds, order, pool,
        [&](std::uint32_t t, std::uint64_t first, std::span<const dataset::MetricPoint> p) {
            events.push_back({t, first, p.size(), false});
            digests[t] = digest(digests[t], p);
        },
        [&](std::uint32_t t) { events.push_back({t, 0, 0, true}); }, las::fields::kAll, 100'000);

    std::size_t e = 0;
    for (const std::uint32_t t : order) {
        std::uint64_t next = 0;
        int batches = 0;
        for (; e < events.size() && !events[e].done; ++e, ++batches) {
            ASSERT_EQ(events[e].tile, t);
            EXPECT_EQ(events[e].first, next);  // file order, nothing skipped
            next += events[e].count;
        }
        EXPECT_EQ(next, ds.tiles[t].tile.header.point_count) << ds.tiles[t].tile.path();
        EXPECT_GE(batches, 4) << "100,000-point batches: several per tile";
        ASSERT_LT(e, events.size());
        EXPECT_EQ(events[e].tile, t);  // its tile_done, before any batch of the next tile
        ++e;
    }
    EXPECT_EQ(e, events.size());

    // Each tile streamed alone gives the same points in the same order.
    for (std::uint32_t t = 0; t < ds.tiles.size(); ++t) {
        std::uint64_t alone = 0;
        dataset::for_each_metric_batch(ds, t, pool, [&](std::uint64_t, std::span<const dataset::MetricPoint> p) {
            alone = digest(alone, p);
        });
        EXPECT_EQ(alone, digests[t]) << ds.tiles[t].tile.path();
    }
}

TEST(PointStream, ColourIsReadOnlyWhenAsked) {
    const auto ds = dataset::open_dataset({(test::surveys_dir() / "ky-woodford-county").string()});
    ThreadPool pool(2);
    const std::uint32_t tiles[] = {0};
    const auto coloured = [&](std::uint32_t fields) {
        std::uint64_t n = 0, black = 0;
        dataset::for_each_metric_batch(
            ds, tiles, pool,
            [&](std::uint32_t, std::uint64_t, std::span<const dataset::MetricPoint> p) {
                for (const auto& m : p) {
                    n += m.coloured;
                    black += m.rgb.r == 0 && m.rgb.g == 0 && m.rgb.b == 0;
                }
            },
            nullptr, fields);
        return std::pair(n, black);
    };
    const auto with = coloured(las::fields::kAll);
    EXPECT_GT(with.first, ds.point_count / 2);
    const auto without = coloured(las::fields::kXyz | las::fields::kClassification);
    EXPECT_EQ(without.first, 0u);
    EXPECT_EQ(without.second, ds.point_count);  // no colour made up
}

class PointStreamFiles : public test::TempDirTest {};

TEST_F(PointStreamFiles, ATileCutShortAfterOpeningIsNamedInTheErrorAfterTheTilesBeforeIt) {
    const fs::path src = test::surveys_dir() / "isprs-filter-test-sites";
    for (const char* name : {"CSite2_orig-utm.laz", "CSite3_orig-utm.laz"}) fs::copy_file(src / name, dir / name);
    const auto ds = dataset::open_dataset({dir.string()});
    ASSERT_EQ(ds.tiles.size(), 2u);
    const std::string cut = ds.tiles[1].tile.path();
    fs::resize_file(cut, fs::file_size(cut) / 2);
    ThreadPool pool(2);
    const std::uint32_t order[] = {0, 1};
    std::uint64_t first_tile_points = 0;
    std::vector<std::uint32_t> done;
    try {
        dataset::for_each_metric_batch(
            ds, order, pool,
            [&](std::uint32_t t, std::uint64_t, std::span<const dataset::MetricPoint> p) {
                if (t == 0) first_tile_points += p.size();
            },
            [&](std::uint32_t t) { done.push_back(t); }, las::fields::kAll, 50'000);
        FAIL() << "a tile cut in half streamed without an error";
    } catch (const Error& e) {
        EXPECT_EQ(e.file(), cut);
        EXPECT_FALSE(e.cause().empty());
    }
    EXPECT_EQ(first_tile_points, ds.tiles[0].tile.header.point_count);
    EXPECT_EQ(done, std::vector<std::uint32_t>{0});
}

TEST_F(PointStreamFiles, CorruptChunkIsSkippedWhenAsked) {
    const auto tile = test::damaged_tile(dir);
    const auto ds = dataset::open_dataset({tile.string()});
    ASSERT_EQ(ds.tiles.size(), 1u);
    ThreadPool pool(2);
    const std::uint32_t tiles[] = {0};
    std::uint64_t points = 0;
    std::vector<dataset::SkippedChunk> skipped;
    const auto add = [&](std::uint32_t, std::uint64_t, std::span<const dataset::MetricPoint> p) { points += p.size(); };
    const auto skip = [&](std::uint32_t, const dataset::SkippedChunk& s) { skipped.push_back(s); };
    dataset::for_each_metric_batch(ds, tiles, pool, add, nullptr, las::fields::kAll, 1u << 20, skip);
    ASSERT_EQ(skipped.size(), 1u);
    EXPECT_EQ(skipped[0].first_point, 450'000u);
    EXPECT_EQ(skipped[0].points, test::kDamagedChunkPoints);
    EXPECT_EQ(skipped[0].error.file, tile.string());
    EXPECT_TRUE(skipped[0].error.offset.has_value());
    EXPECT_EQ(points, ds.tiles[0].tile.header.point_count - test::kDamagedChunkPoints);
    // Without the callback the stream ends with the chunk's error, as before.
    EXPECT_THROW(dataset::for_each_metric_batch(ds, tiles, pool, add, nullptr), Error);
}

}  // namespace
}  // namespace lidarscout
