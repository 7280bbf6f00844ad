// LOD blocks: quadtree codes and the level at which a point first leads its cell; a block's
// points reordered coarse to fine (every point kept, one point per cell per level, the highest);
// the level a camera needs grows as it comes closer; coarse copies keep a prefix; each prefix
// carries its spacing for the adaptive point size.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <random>
#include <tuple>

#include "viewer/point_lod.hpp"

namespace lidarscout::viewer {
namespace {

constexpr double kBlock = 80;

// `n` random points over two blocks side by side (x in [0, 160), y in [0, 80), z 300-330 m).
PointSet random_points(std::size_t n) {
    std::mt19937 rng(7);
    std::uniform_real_distribution<float> x(0, 2 * kBlock - 0.01f), y(0, kBlock - 0.01f), z(0, 30);
    PointSet set;
    set.origin_z = 300;
    for (std::size_t i = 0; i < n; ++i) {
        render::PointAttr p;
        p.dx = x(rng), p.dy = y(rng), p.dz = z(rng);
        p.r = static_cast<std::uint8_t>(i), p.intensity = static_cast<std::uint16_t>(i);
        set.points.push_back(p);
    }
    return set;
}

std::tuple<float, float, float, std::uint16_t> key(const render::PointAttr& p) {
    return {p.dx, p.dy, p.dz, p.intensity};
}

TEST(ViewerPointLod, FirstLevelIsWhereTheCodesPart) {
    EXPECT_EQ(quadtree_code(0, 0), 0u);
    EXPECT_EQ(quadtree_code(0.9999999, 0.9999999), 0xffffffffu);
    EXPECT_EQ(quadtree_code(0.5, 0), 0x40000000u);  // x in the even bits: bit 30 is x's top bit
    EXPECT_EQ(first_level(0x40000000u, 0), 1u);     // the other half in x: apart at level 1
    EXPECT_EQ(first_level(0x80000000u, 0), 1u);
    EXPECT_EQ(first_level(1u, 0), 16u);             // apart only in the finest cell
    EXPECT_EQ(first_level(5u, 5u), kLodLevels - 1); // the same finest cell
}

TEST(ViewerPointLod, BlocksHoldEveryPointCoarseToFineWithTheHighestPerCell) {
    const PointSet set = random_points(20000);
    ThreadPool pool(2);
    const LodBlocks blocks = build_lod_blocks(set, 3, kBlock, pool);
    ASSERT_EQ(blocks.size(), 2u);
    std::vector<std::tuple<float, float, float, std::uint16_t>> in, out;
    for (const auto& p : set.points) in.push_back(key(p));
    for (const auto& b : blocks) {
        EXPECT_EQ(b->tile, 3u);
        EXPECT_EQ(b->level_end.back(), b->points.points.size());
        EXPECT_TRUE(std::is_sorted(b->level_end.begin(), b->level_end.end()));
        EXPECT_EQ(b->level_end[0], 1u);
        for (const auto& p : b->points.points) out.push_back(key(p));
        const double x0 = std::floor(b->bounds.min_x / kBlock) * kBlock;
        for (std::size_t level = 0; level < kLodLevels - 1; ++level) {
            // Per cell of this level: the highest point of the block and the points of the prefix.
            const double cell = kBlock / (1u << level);
            std::map<std::pair<int, int>, std::pair<float, int>> highest_and_count;
            const auto cell_of = [&](const render::PointAttr& p) {
                return std::pair{static_cast<int>((p.dx - x0) / cell), static_cast<int>(p.dy / cell)};
            };
            for (const auto& p : b->points.points) {
                auto& [z, n] = highest_and_count.try_emplace(cell_of(p), -1.0f, 0).first->second;
                z = std::max(z, p.dz);
            }
            for (std::uint32_t i = 0; i < b->level_end[level]; ++i) {
                const auto& p = b->points.points[i];
                auto& [z, n] = highest_and_count.at(cell_of(p));
                ++n;
                EXPECT_EQ(p.dz, z) << "level " << level << ": not the highest point of its cell";
            }
            for (const auto& [c, zn] : highest_and_count) EXPECT_EQ(zn.second, 1) << "level " << level;
        }
    }
    std::sort(in.begin(), in.end());
    std::sort(out.begin(), out.end());
    EXPECT_EQ(in, out);
}

TEST(ViewerPointLod, NearerCamerasNeedFinerLevelsAndCoarseCopiesKeepAPrefix) {
    const PointSet set = random_points(50000);
    ThreadPool pool(1);
    const LodBlocks blocks = build_lod_blocks(set, 0, kBlock, pool);
    const LodBlock& b = *blocks.front();
    render::Camera c;
    c.x = b.bounds.centre_x(), c.y = b.bounds.centre_y(), c.pitch_deg = -90;
    c.width = 640, c.height = 480, c.near_m = 1;
    std::size_t previous = kLodLevels;
    for (double height : {50.0, 200.0, 800.0, 3200.0}) {
        c.z = b.bounds.max_z + height;
        const std::size_t level = level_for(b, c, 0.5);
        EXPECT_LT(level, previous) << height;
        EXPECT_LE(b.spacing(level), 0.5 * pixel_footprint(c, height) + 1e-9);
        previous = level;
    }
    EXPECT_EQ(level_for(b, c, 0), kLodLevels - 1);
    c.z = b.bounds.max_z + 800;
    EXPECT_EQ(lod_batches(blocks, c, 0.5).size(), 2u);
    c.x += 1e4;  // looking at empty ground far away
    EXPECT_TRUE(lod_batches(blocks, c, 0.5).empty());

    const auto coarse = coarse_copy(b, 2.0);
    EXPECT_GE(coarse->spacing(coarse->levels - 1), 2.0);
    EXPECT_LT(coarse->spacing(coarse->levels - 1) / 2, 2.0);
    ASSERT_EQ(coarse->points.points.size(), b.level_end[coarse->levels - 1]);
    EXPECT_LT(coarse->points.points.size(), b.points.points.size());
    for (std::size_t i = 0; i < coarse->points.points.size(); ++i) {
        ASSERT_EQ(key(coarse->points.points[i]), key(b.points.points[i]));
    }
    EXPECT_EQ(coarse->prefix(kLodLevels - 1).points.size(), coarse->points.points.size());
    EXPECT_LT(coarse->bytes(), b.bytes());
}

TEST(ViewerPointLod, PrefixesCarryTheirSpacingAtLeastTheTilesOwn) {
    PointSet set = random_points(50000);
    set.spacing_m = 0.5f;  // as tile_point_set gives a tile's mean spacing
    ThreadPool pool(1);
    const LodBlocks blocks = build_lod_blocks(set, 0, kBlock, pool);
    const LodBlock& b = *blocks.front();
    EXPECT_FLOAT_EQ(b.prefix(0).spacing_m, static_cast<float>(kBlock));  // one point per block
    EXPECT_FLOAT_EQ(b.prefix(3).spacing_m, static_cast<float>(kBlock / 8));
    EXPECT_FLOAT_EQ(b.prefix(10).spacing_m, 0.5f);  // finer cells than the points: the tile's spacing
    EXPECT_FLOAT_EQ(b.prefix(kLodLevels - 1).spacing_m, 0.5f);
    const auto coarse = coarse_copy(b, 2.0);  // what a released tile keeps
    EXPECT_FLOAT_EQ(coarse->prefix(kLodLevels - 1).spacing_m, static_cast<float>(coarse->spacing(coarse->levels - 1)));
    EXPECT_GE(coarse->prefix(kLodLevels - 1).spacing_m, 2.0f);
}

}  // namespace
}  // namespace lidarscout::viewer
