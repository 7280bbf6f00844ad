// The tile index: on a grid of tiles with overlaps, gaps, a tile of a billion metres and tiles
// without bounds, visit() returns what a test of every tile returns and nearest_pending() the tile
// a scan finds, as tiles stop being pending; and a query near one corner of 40,000 tiles looks at
// a few of them, not all.
#include "dataset/tile_index.hpp"

#include <gtest/gtest.h>

#include <limits>
#include <random>
#include <set>

namespace lidarscout::dataset {
namespace {

Bounds box(double x0, double y0, double x1, double y1) { return {x0, y0, 0, x1, y1, 10}; }

bool overlaps(const Bounds& a, const Bounds& b) {
    return a.min_x <= b.max_x && b.min_x <= a.max_x && a.min_y <= b.max_y && b.min_y <= a.max_y;
}

std::vector<Bounds> mixed_tiles() {
    std::mt19937 rng(11);
    std::uniform_real_distribution<double> jitter(-300, 300), size(500, 1600);
    std::vector<Bounds> tiles;
    for (int y = 0; y < 30; ++y) {
        for (int x = 0; x < 30; ++x) {
            if ((x * 7 + y * 3) % 11 == 0) continue;  // gaps
            const double x0 = x * 1000 + jitter(rng), y0 = y * 1000 + jitter(rng);
            tiles.push_back(box(x0, y0, x0 + size(rng), y0 + size(rng)));
        }
    }
    tiles.push_back(box(-1e9, -1e9, 1e9, 1e9));  // a few points in a box of a billion metres
    tiles.push_back(Bounds{});                    // no bounds
    tiles.push_back(box(5000, 5000, 5000, 5000));  // a single point
    return tiles;
}

TEST(TileIndex, VisitAndNearestMatchAScanOfEveryTile) {
    const auto tiles = mixed_tiles();
    TileIndex index(tiles);
    std::mt19937 rng(5);
    std::uniform_real_distribution<double> at(-3000, 33000), side(10, 6000);
    for (int q = 0; q < 100; ++q) {
        const double x = at(rng), y = at(rng), s = side(rng);
        const Bounds query = box(x, y, x + s, y + s);
        std::set<std::uint32_t> seen, expected;
        index.visit([&](const Bounds& b) { return overlaps(b, query); }, [&](std::uint32_t t) { seen.insert(t); });
        for (std::uint32_t t = 0; t < tiles.size(); ++t)
            if (!tiles[t].empty() && overlaps(tiles[t], query)) expected.insert(t);
        EXPECT_EQ(seen, expected);
    }
    for (std::uint32_t t = 0; t < tiles.size(); ++t) index.set_pending(t, true);
    EXPECT_EQ(index.pending_count(), tiles.size() - 1) << "the tile without bounds is never pending";
    std::vector<bool> pending(tiles.size(), true);
    pending[tiles.size() - 2] = false;
    std::size_t taken = 0;
    for (int q = 0; q < 300; ++q) {
        const double x = at(rng), y = at(rng);
        double best = std::numeric_limits<double>::infinity();
        for (std::uint32_t t = 0; t < tiles.size(); ++t)
            if (pending[t]) best = std::min(best, tiles[t].distance_xy(x, y));
        const auto found = index.nearest_pending(x, y);
        ASSERT_TRUE(found);
        EXPECT_DOUBLE_EQ(tiles[*found].distance_xy(x, y), best);
        if (*found != tiles.size() - 3) {  // the huge one stays: it is nearest to everything
            index.set_pending(*found, false);
            pending[*found] = false;
            ++taken;
        }
    }
    index.set_pending(tiles.size() - 3, false);
    std::size_t left = 0;
    while (const auto t = index.nearest_pending(0, 0)) {
        index.set_pending(*t, false);
        ++left;
    }
    EXPECT_GT(taken, 50u);
    EXPECT_EQ(left, tiles.size() - 2 - taken) << "every pending tile comes out once";
}

TEST(TileIndex, QueriesNearOneCornerLookAtFewTiles) {
    std::vector<Bounds> tiles;
    for (int y = 0; y < 200; ++y)
        for (int x = 0; x < 200; ++x) tiles.push_back(box(x * 1e3, y * 1e3, x * 1e3 + 1e3, y * 1e3 + 1e3));
    TileIndex index(tiles);
    for (std::uint32_t t = 0; t < tiles.size(); ++t) index.set_pending(t, true);
    std::uint64_t before = index.visits();
    const auto t = index.nearest_pending(2500, 3500);
    ASSERT_TRUE(t);
    EXPECT_EQ(*t, 3u * 200 + 2);
    EXPECT_LE(index.visits() - before, 400u) << "of " << tiles.size() << " tiles";
    before = index.visits();
    std::size_t found = 0;
    const Bounds query = box(10'000, 10'000, 14'500, 14'500);
    index.visit([&](const Bounds& b) { return overlaps(b, query); }, [&](std::uint32_t) { ++found; });
    EXPECT_EQ(found, 36u);  // x and y from 9,000-10,000 to 14,000-15,000, edges touching included
    EXPECT_LE(index.visits() - before, 1000u) << "of " << tiles.size() << " tiles";
}

// The k nearest pending tiles come from one search, in the order k single asks give them (ties by the lower
// index), and a ring of tiles done around the point is passed once for all k, not once for each.
TEST(TileIndex, ManyNearestAtOnceAreTheSingleAsksInOrder) {
    std::vector<Bounds> tiles;
    for (int y = 0; y < 150; ++y)
        for (int x = 0; x < 150; ++x) tiles.push_back(box(x * 1e3, y * 1e3, x * 1e3 + 1e3, y * 1e3 + 1e3));
    tiles.push_back(box(-5e6, -5e6, 5e6, 5e6));  // apart: nearest to everything
    TileIndex index(tiles), single(tiles);
    for (std::uint32_t t = 0; t < tiles.size(); ++t) index.set_pending(t, true), single.set_pending(t, true);
    std::mt19937 rng(11);
    std::uniform_real_distribution<double> at(-2e4, 1.7e5);
    for (int q = 0; q < 40; ++q) {
        const double x = at(rng), y = at(rng);
        const auto many = index.nearest_pending(x, y, 37);
        std::vector<std::uint32_t> one_by_one;
        for (int k = 0; k < 37; ++k) {
            const auto t = single.nearest_pending(x, y);
            ASSERT_TRUE(t);
            one_by_one.push_back(*t);
            single.set_pending(*t, false);
        }
        ASSERT_EQ(many, one_by_one) << "query " << q;
        for (const auto t : many) index.set_pending(t, false);
    }
    // Every tile within 40 km of the middle done: the next 32 from one search cost about one ring, not 32.
    TileIndex ring(tiles);
    for (std::uint32_t t = 0; t + 1 < tiles.size(); ++t) {
        if (tiles[t].distance_xy(75e3, 75e3) > 40e3) ring.set_pending(t, true);
    }
    std::uint64_t before = ring.visits();
    const auto next = ring.nearest_pending(75e3, 75e3, 32);
    const std::uint64_t batched = ring.visits() - before;
    ASSERT_EQ(next.size(), 32u);
    for (std::size_t k = 1; k < next.size(); ++k) {
        EXPECT_LE(tiles[next[k - 1]].distance_xy(75e3, 75e3), tiles[next[k]].distance_xy(75e3, 75e3));
    }
    before = ring.visits();
    ASSERT_TRUE(ring.nearest_pending(75e3, 75e3));
    const std::uint64_t one = ring.visits() - before;
    EXPECT_LT(batched, 3 * one) << "32 tiles found with " << batched << " visits, one with " << one;
    EXPECT_TRUE(index.nearest_pending(0, 0, 0).empty());
}

}  // namespace
}  // namespace lidarscout::dataset
