// Patch detail from full-resolution points: the per-texel means of a tile's points, merged
// count-weighted with another tile's, and laid over a heightmap where points fell.
#include "viewer/scheduler_detail.hpp"

#include <gtest/gtest.h>

#include <cmath>

#include "render/framebuffer.hpp"

namespace lidarscout::viewer {
namespace {

constexpr double kOx = 500'000.0, kOy = 4'000'000.0;

PatchDetail detail_with(int texel, float height, std::uint32_t count, std::uint32_t colour) {
    PatchDetail d;
    d.origin_x = kOx, d.origin_y = kOy, d.texel_m = 10, d.size = 4;
    d.height.assign(16, NAN), d.count.assign(16, 0), d.colour.assign(16, 0);
    d.height[texel] = height, d.count[texel] = count, d.colour[texel] = colour;
    return d;
}

TEST(ViewerSchedulerDetail, MergeIsTheCountWeightedMean) {
    auto a = detail_with(5, 10.0f, 1, render::pack_rgba(0, 0, 0));
    const auto b = detail_with(5, 20.0f, 3, render::pack_rgba(200, 100, 40));
    merge_detail(a, b);
    EXPECT_FLOAT_EQ(a.height[5], 17.5f);
    EXPECT_EQ(a.count[5], 4u);
    EXPECT_NEAR(render::red(a.colour[5]), 150, 1);
    EXPECT_TRUE(std::isnan(a.height[0]));
    merge_detail(a, detail_with(0, 3.0f, 2, render::pack_rgba(1, 2, 3)));  // a texel only the other has
    EXPECT_FLOAT_EQ(a.height[0], 3.0f);
    EXPECT_EQ(a.count[0], 2u);
}

TEST(ViewerSchedulerDetail, OverlayReplacesOnlyTexelsWithPoints) {
    PatchHeightmap base;
    base.origin_x = kOx, base.origin_y = kOy, base.texel_m = 10, base.size = 4;
    base.heights.assign(16, 1.0f);
    base.colours.assign(16, render::pack_rgba(9, 9, 9));
    const auto out = overlay_detail(base, detail_with(6, 42.0f, 5, render::pack_rgba(200, 0, 0)));
    EXPECT_FLOAT_EQ(out.heights[6], 42.0f);
    EXPECT_EQ(render::red(out.colours[6]), 200);
    EXPECT_FLOAT_EQ(out.heights[7], 1.0f);
    EXPECT_EQ(render::red(out.colours[7]), 9);
}

}  // namespace
}  // namespace lidarscout::viewer
