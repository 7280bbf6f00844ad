// The synthetic landscape's pure functions: noise ranges and determinism, the river, the
// layout, and TerrainPatch answers that do not depend on the rectangle sampled (tile seams).
#include <gtest/gtest.h>

#include <cmath>

#include "core/error.hpp"

#include "core/random.hpp"
#include "synth/buildings.hpp"
#include "synth/flight_plan.hpp"
#include "synth/noise.hpp"
#include "synth/terrain_model.hpp"
#include "synth/terrain_patch.hpp"
#include "synth/vegetation.hpp"

namespace lidarscout::synth {
namespace {

Area area_of(std::uint32_t tiles) {
    Area a;
    a.tiles = tiles;
    return a;
}

TEST(TerrainNoise, RangesAndDeterminism) {
    double lo = 1e9, hi = -1e9, sum = 0;
    int differ = 0;
    Rng rng(42);
    for (int i = 0; i < 20000; ++i) {
        const double x = rng.uniform(-1000, 1000), y = rng.uniform(-1000, 1000);
        const double n = gradient_noise(7, x, y);
        EXPECT_EQ(n, gradient_noise(7, x, y));
        differ += n != gradient_noise(8, x, y);
        lo = std::min(lo, n);
        hi = std::max(hi, n);
        sum += n;
        const double r = ridged_noise(7, x, y, 4);
        ASSERT_GE(r, 0.0);
        ASSERT_LE(r, 1.0);
        const double v = fractal_noise_1d(7, x, 3);
        ASSERT_GE(v, -1.0);
        ASSERT_LE(v, 1.0);
    }
    EXPECT_GE(lo, -1.05);
    EXPECT_LE(hi, 1.05);
    EXPECT_LT(lo, -0.5);  // it does use its range
    EXPECT_GT(hi, 0.5);
    EXPECT_LT(std::fabs(sum / 20000), 0.05);
    EXPECT_GT(differ, 19000);
    EXPECT_EQ(gradient_noise(7, 3.0, 4.0), 0.0);  // zero on the lattice
}

TEST(TerrainNoise, FixedHashValues) {
    // The generator's output depends on these exact values: a change here changes every demo.
    EXPECT_EQ(mix64(0), 0xE220A8397B1DCDAFull);
    EXPECT_EQ(hash_of(1, 2, 3), hash_of(1, 2, 3));
    EXPECT_NE(hash_of(1, 2, 3), hash_of(1, 3, 2));
    Rng a(5), b(5);
    for (int i = 0; i < 100; ++i) EXPECT_EQ(a.next(), b.next());
    EXPECT_EQ(unit_of(0), 0.0);
    EXPECT_LT(unit_of(~0ull), 1.0);
}

TEST(TerrainModel, RiverFlowsSouthInItsValley) {
    const TerrainModel model(1, area_of(4));
    const Area& a = model.area();
    for (double y = a.y0; y <= a.y1(); y += 100) {
        const RiverRow r = model.relief().river(y);
        EXPECT_GT(r.centre, a.x0);
        EXPECT_LT(r.centre, a.x1());
        EXPECT_GE(r.half_width, 5.0);
        EXPECT_LE(r.half_width, 13.0);
        EXPECT_LT(r.water_level, model.relief().river(y + 100).water_level);  // downstream is south
        EXPECT_LT(model.relief().ground(r.centre, y, r), r.water_level);      // the bed is under water
        EXPECT_GT(model.relief().ground(r.centre + r.half_width + 10, y, r), r.water_level);  // the bank is dry
    }
}

TEST(TerrainModel, LayoutHasAVillageAndFarmsInTheArea) {
    const TerrainModel model(1, area_of(8));
    const Area& a = model.area();
    int villages = 0, farms = 0;
    for (const auto& v : model.layout().villages()) {
        (v.farm ? farms : villages)++;
        EXPECT_GE(v.x, a.x0);
        EXPECT_LE(v.x, a.x1());
    }
    EXPECT_GE(villages, 1);
    EXPECT_GE(farms, 5);
}

TEST(TerrainModel, CellsAreDeterministic) {
    const TerrainModel model(3, area_of(2));
    const auto villages =
        model.layout().villages_near(model.area().x0, model.area().y0, model.area().x1(), model.area().y1(), 100);
    int buildings = 0, trees = 0;
    for (int j = 0; j < 30; ++j) {
        for (int i = 0; i < 30; ++i) {
            const auto b1 = building_in_cell(model, i, j, villages), b2 = building_in_cell(model, i, j, villages);
            ASSERT_EQ(b1.has_value(), b2.has_value());
            if (b1) {
                ++buildings;
                EXPECT_EQ(b1->x, b2->x);
                EXPECT_TRUE(b1->covers(b1->x, b1->y));
                // Wholly inside its own cell: every corner of the footprint.
                const double x0 = model.area().x0 + i * kBuildingCell, y0 = model.area().y0 + j * kBuildingCell;
                for (double su : {-1.0, 1.0}) {
                    for (double sw : {-1.0, 1.0}) {
                        const double x = b1->x + su * b1->half_length * b1->cos_a - sw * b1->half_width * b1->sin_a;
                        const double y = b1->y + su * b1->half_length * b1->sin_a + sw * b1->half_width * b1->cos_a;
                        EXPECT_GT(x, x0);
                        EXPECT_LT(x, x0 + kBuildingCell);
                        EXPECT_GT(y, y0);
                        EXPECT_LT(y, y0 + kBuildingCell);
                    }
                }
            }
            const auto t1 = tree_in_cell(model, i, j, villages), t2 = tree_in_cell(model, i, j, villages);
            ASSERT_EQ(t1.tree.has_value(), t2.tree.has_value());
            EXPECT_EQ(t1.forest, t2.forest);
            if (t1.tree) {
                ++trees;
                EXPECT_EQ(t1.tree->height, t2.tree->height);
                EXPECT_LE(t1.tree->crown_radius, kTreeCell);
            }
        }
    }
    EXPECT_GT(trees, 50);
}

TEST(TerrainModel, PatchesAgreeWhereTheyOverlap) {
    const TerrainModel model(1, area_of(2));
    const Area& a = model.area();
    const TerrainPatch left(model, a.x0 + 400, a.y0 + 400, a.x0 + 502, a.y0 + 600);
    const TerrainPatch right(model, a.x0 + 498, a.y0 + 300, a.x0 + 700, a.y0 + 620);
    Rng rng(9);
    for (int k = 0; k < 20000; ++k) {
        const double x = rng.uniform(a.x0 + 498, a.x0 + 502), y = rng.uniform(a.y0 + 400, a.y0 + 600);
        const Column p = left.column(x, y), q = right.column(x, y);
        ASSERT_EQ(p.ground_z, q.ground_z);
        ASSERT_EQ(p.ground_class, q.ground_class);
        ASSERT_EQ(p.top, q.top);
        ASSERT_EQ(p.top_z, q.top_z);
        ASSERT_EQ(p.colour.r, q.colour.r);
        ASSERT_EQ(left.ground(x, y), right.ground(x, y));
    }
    EXPECT_THROW(left.column(a.x0 + 100, a.y0 + 500), Error);
}

TEST(TerrainFlightPlan, StripsCoverTheAreaAtTheRequestedDensity) {
    for (std::uint32_t tiles : {1u, 2u, 3u, 8u}) {
        const Area area = area_of(tiles);
        const FlightPlan p = plan_flight(1, area, 5.0);
        EXPECT_LE(p.centre(0) - p.half_swath, area.x0) << tiles;
        EXPECT_GE(p.centre(p.strips - 1) + p.half_swath, area.x1()) << tiles;
        EXPECT_LT(p.strip_spacing, 2 * p.half_swath);  // neighbouring strips overlap
        double covered = 0;
        for (std::uint32_t k = 0; k < p.strips; ++k) {
            covered += std::max(
                0.0, std::min(area.x1(), p.centre(k) + p.half_swath) - std::max(area.x0, p.centre(k) - p.half_swath));
            if (k > 0) {
                EXPECT_GT(p.strip_time(k), p.strip_time(k - 1) + p.lines_per_strip * p.line_spacing / p.speed);
            }
        }
        const double density = covered / area.size() / (p.line_spacing * p.pulse_spacing);
        EXPECT_NEAR(density, 5.0, 1e-9) << tiles;
        EXPECT_GE(p.lines_per_strip * p.line_spacing, area.size() + 2 * p.run_in - 1e-6);
    }
}

}  // namespace
}  // namespace lidarscout::synth
