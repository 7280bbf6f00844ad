// The region split shared by train-data and eval: deterministic per (seed, dataset), the
// validation share follows the fraction, windows straddling the two sides are Border, and bad
// options are refused.
#include <gtest/gtest.h>

#include "core/error.hpp"
#include "pipelines/region_split.hpp"

namespace lidarscout::pipelines {
namespace {

TEST(RegionSplit, DeterministicPerSeedAndDataset) {
    const RegionSplitOptions o;
    const RegionSplit a(o, "survey"), b(o, "survey"), other_name(o, "another");
    RegionSplitOptions o2 = o;
    o2.seed = 2;
    const RegionSplit other_seed(o2, "survey");
    int differ_name = 0, differ_seed = 0;
    for (int bx = -20; bx < 20; ++bx) {
        for (int by = -20; by < 20; ++by) {
            ASSERT_EQ(a.of_block(bx, by), b.of_block(bx, by));
            differ_name += a.of_block(bx, by) != other_name.of_block(bx, by);
            differ_seed += a.of_block(bx, by) != other_seed.of_block(bx, by);
        }
    }
    EXPECT_GT(differ_name, 100);
    EXPECT_GT(differ_seed, 100);
}

TEST(RegionSplit, ValidationShareFollowsTheFraction) {
    RegionSplitOptions o;
    o.val_fraction = 0.25;
    const RegionSplit s(o, "x");
    int val = 0;
    for (int bx = 0; bx < 100; ++bx) {
        for (int by = 0; by < 100; ++by) val += s.of_block(bx, by) == Split::Validation;
    }
    EXPECT_NEAR(val / 10000.0, 0.25, 0.02);
    o.val_fraction = 0;
    EXPECT_EQ(RegionSplit(o, "x").of_block(3, 4), Split::Train);
    o.val_fraction = 1;
    EXPECT_EQ(RegionSplit(o, "x").of_block(3, 4), Split::Validation);
}

TEST(RegionSplit, WindowsInsideABlockTakeItsSideAndStraddlingOnesAreBorder) {
    RegionSplitOptions o;
    o.block_m = 1000;
    o.val_fraction = 0.5;
    const RegionSplit s(o, "x");
    // Two horizontally adjacent blocks on different sides.
    int bx = 0;
    while (s.of_block(bx, 0) == s.of_block(bx + 1, 0)) ++bx;
    const double x0 = bx * 1000.0;
    EXPECT_EQ(s.of_window(x0 + 500, 500, x0 + 100, 100, x0 + 900, 900), s.of_block(bx, 0));
    EXPECT_EQ(s.of_window(x0 + 1500, 500, x0 + 1100, 100, x0 + 1900, 900), s.of_block(bx + 1, 0));
    EXPECT_EQ(s.of_window(x0 + 900, 500, x0 + 500, 100, x0 + 1300, 900), Split::Border);
}

TEST(RegionSplit, BadOptionsAreRefused) {
    RegionSplitOptions o;
    o.block_m = 0;
    EXPECT_THROW(RegionSplit(o, "x"), Error);
    o.block_m = 100;
    o.val_fraction = 1.5;
    EXPECT_THROW(RegionSplit(o, "x"), Error);
    EXPECT_STREQ(split_name(Split::Validation), "validation");
}

}  // namespace
}  // namespace lidarscout::pipelines
