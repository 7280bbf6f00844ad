// The block gridders on points placed by hand: idw's weights and radius, a tin exact on a plane
// with nodata outside the hull and in triangles with long edges, highest-tin equal to a tin of the
// highest point per texel in its holes, a thinned tin equal to the whole one, and the reach of each
// method.
#include "raster/block_gridders.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <map>

#include "core/error.hpp"

namespace lidarscout::raster {
namespace {

DemGrid small_grid(int block) {
    DemGrid g;
    g.origin_x = 1000, g.origin_y = 2000, g.texel_m = 1, g.width = block, g.height = block, g.block = block;
    return g;
}

// A grid of 3 x 3 blocks of n texels whose middle block, {1, 1}, is small_grid(n)'s block.
DemGrid middle_block_grid(int n) {
    DemGrid g = small_grid(n);
    g.width = g.height = 3 * n;
    g.origin_x -= n, g.origin_y -= n;
    return g;
}

// A repeatable random number in [0, 1) (a linear congruential generator).
struct Random {
    std::uint32_t seed;
    double operator()() { return (seed = seed * 1664525u + 1013904223u) / 4294967296.0; }
};

// What a tin gridder of `spec` (its method set to Tin) makes of `points` in block {1, 1} of `g`.
BlockImages tin_block(GridderSpec spec, const DemGrid& g, const std::vector<dataset::MetricPoint>& points) {
    spec.method = GridMethod::Tin;
    auto gridder = make_block_gridder(spec, g, {1, 1});
    for (const auto& p : points) gridder->add(p, nullptr);
    return gridder->finish();
}

dataset::MetricPoint point(double x, double y, double z, std::uint8_t red = 0) {
    dataset::MetricPoint p;
    p.x = x, p.y = y, p.z = z, p.rgb = {red, 0, 0};
    return p;
}

TEST(BlockGridders, IdwIsTheInverseSquareDistanceMeanWithinTheRadius) {
    GridderSpec spec;
    spec.method = GridMethod::Idw;
    spec.idw_radius_m = 1.0;
    spec.rgb = true;
    const auto g = small_grid(4);
    auto gridder = make_block_gridder(spec, g, {0, 0});
    // texel (1, 1) has its centre at (1001.5, 2001.5)
    gridder->add(point(1001.5 + 0.5, 2001.5, 10, 100), nullptr);  // 0.5 m from it: weight 4
    gridder->add(point(1001.5, 2001.5 - 0.25, 20, 200), nullptr);  // 0.25 m: weight 16
    const auto images = gridder->finish();
    const auto at = [&](int col, int row) { return images.heights_m[static_cast<std::size_t>(row) * 4 + col]; };
    EXPECT_NEAR(at(1, 1), (4 * 10 + 16 * 20) / 20.0, 1e-5);
    EXPECT_NEAR(at(2, 1), 10.0, 1e-5);     // only the first within 1 m (0.5 m away)
    EXPECT_TRUE(std::isnan(at(3, 3)));     // none within 1 m
    EXPECT_TRUE(std::isnan(at(0, 0)));     // the second is 1.03 m away
    const std::size_t n = 16;
    EXPECT_EQ(images.rgba[1 * 4 + 1], std::lround((4 * 100 + 16 * 200) / 20.0));  // red, weighted the same
    EXPECT_EQ(images.rgba[3 * n + 1 * 4 + 1], 255);
    EXPECT_EQ(images.rgba[3 * n + 15], 0);
}

TEST(BlockGridders, TinIsExactOnAPlaneAndEmptyOutsideTheHull) {
    GridderSpec spec;
    spec.method = GridMethod::Tin;
    const auto g = small_grid(32);
    auto gridder = make_block_gridder(spec, g, {0, 0});
    const auto plane = [](double x, double y) { return 100 + 0.5 * (x - 1000) - 0.25 * (y - 2000); };
    for (int i = 0; i < 40; ++i) {  // scattered over [0, 20] x [0, 20] m of the block
        const double x = 1000 + std::fmod(i * 7.31, 20.0), y = 2000 + std::fmod(i * 3.97 + i * i * 0.11, 20.0);
        gridder->add(point(x, y, plane(x, y)), nullptr);
    }
    for (const auto& corner : {std::pair{0.0, 0.0}, {20.0, 0.0}, {0.0, 20.0}, {20.0, 20.0}}) {
        gridder->add(point(1000 + corner.first, 2000 + corner.second, plane(1000 + corner.first, 2000 + corner.second)),
                     nullptr);
    }
    const auto images = gridder->finish();
    for (int row = 0; row < 32; ++row) {
        for (int col = 0; col < 32; ++col) {
            const float h = images.heights_m[static_cast<std::size_t>(row) * 32 + col];
            if (col < 20 && row < 20) {
                EXPECT_NEAR(h, plane(1000 + col + 0.5, 2000 + row + 0.5), 1e-3) << col << ", " << row;
            } else {
                EXPECT_TRUE(std::isnan(h)) << col << ", " << row;
            }
        }
    }
}

TEST(BlockGridders, TinLeavesNodataInTrianglesWithLongEdges) {
    GridderSpec spec;
    spec.method = GridMethod::Tin;
    const auto g = small_grid(64);
    // two dense strips 40 m apart: only long triangles span the gap between them
    const auto fill = [&](BlockGridder& gridder) {
        for (int i = 0; i <= 40; ++i) {
            for (const double x : {0.0, 2.0, 4.0, 44.0, 46.0, 48.0}) gridder.add(point(1000 + x, 2000 + i, 5), nullptr);
        }
    };
    auto open = make_block_gridder(spec, g, {0, 0});
    fill(*open);
    const auto filled = open->finish();
    spec.tin_max_edge_m = 10;
    auto cut = make_block_gridder(spec, g, {0, 0});
    fill(*cut);
    const auto killed = cut->finish();
    const std::size_t gap = 20 * 64 + 24, strip = 20 * 64 + 2;  // (24, 20) in the gap, (2, 20) in a strip
    EXPECT_FLOAT_EQ(filled.heights_m[gap], 5.0f);
    EXPECT_TRUE(std::isnan(killed.heights_m[gap]));
    EXPECT_FLOAT_EQ(killed.heights_m[strip], 5.0f);
}

// highest-tin: the highest point where a texel has one; elsewhere exactly the TIN of those highest
// points (a Tin gridder given them), with the same edge limit: over scattered holes (settled from
// the texels around them), a wide gap and beyond the data (settled by the TIN of the points near them).
TEST(BlockGridders, HighestTinIsTheTinOfTheHighestPointsInItsHoles) {
    const int n = 64;
    const DemGrid g = middle_block_grid(n);  // block (1, 1) has a block of points on every side
    GridderSpec spec;
    spec.method = GridMethod::HighestTin;
    spec.tin_max_edge_m = 6;
    auto highest = make_block_gridder(spec, g, {1, 1});
    std::map<std::pair<long, long>, dataset::MetricPoint> top;  // the highest point per texel
    Random random{12345};
    for (int i = 0; i < 24000; ++i) {
        const double x = 1000 - 40 + random() * 90, y = 2000 - 40 + random() * 130;  // none east of x 1050
        if (std::hypot(x - 1030, y - 2035) < 9) continue;  // a pond
        const auto p = point(x, y, 50 + 3 * std::sin(x * 0.3) + random() * 2);
        highest->add(p, nullptr);
        const std::pair<long, long> t{std::lround(std::floor(x - g.origin_x)), std::lround(std::floor(y - g.origin_y))};
        if (!top.count(t) || top[t].z < p.z) top[t] = p;
    }
    spec.method = GridMethod::Tin;
    auto tin = make_block_gridder(spec, g, {1, 1});
    for (const auto& [texel, p] : top) tin->add(p, nullptr);
    const auto a = highest->finish(), b = tin->finish();
    std::size_t holes = 0, filled = 0;
    for (int row = 0; row < n; ++row) {
        for (int col = 0; col < n; ++col) {
            const std::size_t i = static_cast<std::size_t>(row) * n + col;
            const auto it = top.find({col + n, row + n});
            if (it != top.end()) {
                EXPECT_FLOAT_EQ(a.heights_m[i], static_cast<float>(it->second.z)) << col << ", " << row;
                continue;
            }
            ++holes;
            filled += !std::isnan(a.heights_m[i]);
            if (std::isnan(b.heights_m[i])) {
                EXPECT_TRUE(std::isnan(a.heights_m[i])) << col << ", " << row;
            } else {
                EXPECT_NEAR(a.heights_m[i], b.heights_m[i], 1e-3) << col << ", " << row;
            }
        }
    }
    EXPECT_GT(holes, 400u);  // scattered, the pond, beyond the data
    EXPECT_GT(filled, 100u);
    EXPECT_LT(filled, holes);
}

// TinSearch: the triangles found locally (with the points near the unproven texels triangulated)
// give the rasters that triangulating every point gives: random points with colour (5 and 0.3 per
// texel: the sparse ones leave slivers along the hull unproven), a pond and no points beyond
// x 1050, with and without an edge limit.
TEST(BlockGridders, TinFindsTheSameTrianglesLocallyAsByTriangulating) {
    const int n = 64;
    const DemGrid g = middle_block_grid(n);
    for (const int count : {60000, 3500})
    for (const double max_edge : {0.0, 6.0}) {
        std::vector<dataset::MetricPoint> points;
        Random random{777};
        for (int i = 0; i < count; ++i) {
            const double x = 1000 - 40 + random() * 90, y = 2000 - 40 + random() * 130;
            if (std::hypot(x - 1030, y - 2035) < 9) continue;
            const double z = 50 + 3 * std::sin(x * 0.3) + random() * 2;
            points.push_back(point(x, y, z, static_cast<std::uint8_t>(random() * 255)));
        }
        const auto grid_with = [&](TinSearch search) {
            GridderSpec spec;
            spec.rgb = true;
            spec.tin_max_edge_m = max_edge;
            spec.tin_search = search;
            return tin_block(spec, g, points);
        };
        const BlockImages local = grid_with(TinSearch::Local), whole = grid_with(TinSearch::Triangulate);
        std::size_t values = 0;
        for (std::size_t i = 0; i < whole.heights_m.size(); ++i) {
            ASSERT_EQ(std::isnan(local.heights_m[i]), std::isnan(whole.heights_m[i])) << i << " at " << max_edge;
            if (std::isnan(whole.heights_m[i])) continue;
            ++values;
            EXPECT_NEAR(local.heights_m[i], whole.heights_m[i], 1e-4) << i;
        }
        for (std::size_t i = 0; i < whole.rgba.size(); ++i) EXPECT_NEAR(local.rgba[i], whole.rgba[i], 1) << i;
        EXPECT_GT(values, 2000u);
        EXPECT_LT(values, std::size_t(n * n) - 300);  // the pond (at a 6 m limit) and beyond x 1050 stay empty
    }
}

// A wide pond among dense points (40 per square metre, 20 m of radius): the long triangles over it
// found from the points of its rim, as the whole TIN has them.
TEST(BlockGridders, TinOverAWidePondIsTheWholeTins) {
    const int n = 64;
    const DemGrid g = middle_block_grid(n);
    std::vector<dataset::MetricPoint> points;
    Random random{99};
    for (int i = 0; i < 282000; ++i) {
        const double x = 990 + random() * 84, y = 1990 + random() * 84;
        if (std::hypot(x - 1032, y - 2032) < 20) continue;
        points.push_back(point(x, y, 10 + 0.1 * x - 0.05 * y + random()));
    }
    const auto grid_with = [&](TinSearch search) {
        GridderSpec spec;
        spec.tin_search = search;
        return tin_block(spec, g, points);
    };
    const BlockImages local = grid_with(TinSearch::Local), whole = grid_with(TinSearch::Triangulate);
    const std::size_t centre = 32 * 64 + 32;
    ASSERT_FALSE(std::isnan(whole.heights_m[centre]));  // the pond is spanned by long triangles
    for (std::size_t i = 0; i < whole.heights_m.size(); ++i) {
        ASSERT_EQ(std::isnan(local.heights_m[i]), std::isnan(whole.heights_m[i])) << i;
        if (!std::isnan(whole.heights_m[i])) EXPECT_NEAR(local.heights_m[i], whole.heights_m[i], 1e-4) << i;
    }
}

// Thinning (GridderSpec::tin_thinning): a dense block (60 points per square metre) with a pond wider
// than the edge limit, a diagonal edge of the survey, two sparse strips and a lattice of points with
// ties (on texel centres, four on a circle) gives what the walk over every point and CGAL's whole
// triangulation give, texel for texel; the tally shows every stage at work.
TEST(BlockGridders, ThinnedTinIsTheWholeTin) {
    const int n = 64;
    const DemGrid g = middle_block_grid(n);
    std::vector<dataset::MetricPoint> points;
    Random random{4242};
    const auto height = [](double x, double y) { return 50 + 3 * std::sin(x * 0.2) + 0.1 * y; };
    const auto colour = [&] { return static_cast<std::uint8_t>(random() * 255); };
    for (int i = 0; i < 440000; ++i) {
        const double x = 985 + random() * 94, y = 1985 + random() * 94;
        if (std::hypot(x - 1025, y - 2025) < 10) continue;       // the pond
        if (x > 1050 + 0.3 * (y - 2000)) continue;                  // beyond the survey's edge
        if (y > 2050 && y < 2054 && random() > 0.03) continue;     // the sparse strip: 2 a square metre
        if (y > 2008 && y < 2016 && random() > 0.003) continue;    // a sparser one: 0.2 (triangles of 2-5 m)
        points.push_back(point(x, y, height(x, y) + random() * 0.5, colour()));
    }
    for (double x = 1005; x <= 1015; x += 0.25) {  // the lattice: ties everywhere
        for (double y = 2040; y <= 2046; y += 0.25) points.push_back(point(x, y, height(x, y), colour()));
    }
    const auto grid_with = [&](bool thinning, TinSearch search, TinThinningTally* tally) {
        GridderSpec spec;
        spec.rgb = true;
        spec.tin_max_edge_m = 6;
        spec.tin_search = search;
        spec.tin_thinning = thinning;
        spec.thinning_tally = tally;
        return tin_block(spec, g, points);
    };
    TinThinningTally tally;
    const BlockImages thinned = grid_with(true, TinSearch::Auto, &tally);
    const BlockImages every = grid_with(false, TinSearch::Auto, nullptr);
    const BlockImages whole = grid_with(false, TinSearch::Triangulate, nullptr);
    std::size_t values = 0;
    for (std::size_t i = 0; i < every.heights_m.size(); ++i) {
        ASSERT_EQ(std::isnan(thinned.heights_m[i]), std::isnan(every.heights_m[i])) << i;
        ASSERT_EQ(std::isnan(thinned.heights_m[i]), std::isnan(whole.heights_m[i])) << i;
        if (std::isnan(every.heights_m[i])) continue;
        ++values;
        EXPECT_NEAR(thinned.heights_m[i], every.heights_m[i], 1e-4) << i;
        EXPECT_NEAR(thinned.heights_m[i], whole.heights_m[i], 1e-4) << i;
    }
    EXPECT_EQ(thinned.rgba, every.rgba);
    for (std::size_t i = 0; i < whole.rgba.size(); ++i) EXPECT_NEAR(thinned.rgba[i], whole.rgba[i], 1) << i;
    EXPECT_GT(values, 2500u);
    EXPECT_LT(values, std::size_t(n * n) - 400);  // the pond and beyond the edge stay empty
    EXPECT_EQ(tally.blocks.load(), 1u);
    EXPECT_EQ(tally.first + tally.later + tally.whole, std::uint64_t(n * n));
    EXPECT_GT(tally.first.load(), std::uint64_t(n * n) / 2);
    EXPECT_GT(tally.later.load(), 0u);
}

TEST(BlockGridders, ReachAndParametersAreChecked) {
    GridderSpec spec;
    EXPECT_EQ(gridder_reach_m(spec, 2.0), 0.0);
    spec.method = GridMethod::Idw;
    EXPECT_NEAR(gridder_reach_m(spec, 2.0), 2.0 * std::sqrt(2.0), 1e-12);
    spec.idw_radius_m = 5;
    EXPECT_EQ(gridder_reach_m(spec, 2.0), 5.0);
    spec.idw_power = 0;
    EXPECT_THROW(make_block_gridder(spec, small_grid(8), {0, 0}), Error);
    spec.method = GridMethod::Tin;  // no edge limit: the widest margin
    EXPECT_EQ(gridder_reach_m(spec, 2.0), kMaxTinMarginTexels * 2.0);
    EXPECT_THROW(make_block_gridder(spec, small_grid(512), {0, 0}), Error);  // no room for the margin
    EXPECT_NO_THROW(make_block_gridder(spec, small_grid(tin_block_texels(kMaxTinMarginTexels)), {0, 0}));
}

TEST(BlockGridders, TinMarginsAreWhatTheGridderReaches) {
    GridderSpec spec;
    EXPECT_EQ(tin_margin_texels(spec, 1.0), 0);  // not a tin
    EXPECT_EQ(tin_block_texels(0), 512);
    spec.method = GridMethod::HighestTin;
    spec.tin_max_edge_m = 20;
    EXPECT_EQ(tin_margin_texels(spec, 1.0), 24);  // the longest edge and 4 texels
    EXPECT_EQ(tin_margin_texels(spec, 10.0), 6);
    EXPECT_EQ(gridder_reach_m(spec, 10.0), 60.0);
    spec.method = GridMethod::Tin;
    spec.ground = recon::GroundFilterParams{};  // 1 m cells, an 18 m window: openings reaching 36 cells
    EXPECT_EQ(tin_margin_texels(spec, 1.0), 42);  // 36 + 2 cells (slopes, sampling) + 4 texels
    EXPECT_EQ(tin_margin_texels(spec, 0.5), 64);  // 80 texels needed: at most the widest
    spec.tin_max_edge_m = 1000;
    EXPECT_EQ(tin_margin_texels(spec, 1.0), kMaxTinMarginTexels);
    EXPECT_EQ(tin_block_texels(42), 428);
    // a block of the widest margin's size has room; one of a narrower margin's has not
    spec.tin_max_edge_m = 0;
    EXPECT_THROW(make_block_gridder(spec, small_grid(tin_block_texels(42)), {0, 0}), Error);
}

}  // namespace
}  // namespace lidarscout::raster
