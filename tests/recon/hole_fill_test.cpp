// Pull-push hole filling: a hole in a plane is filled close to the plane, holes not asked for
// stay, and a raster without any defined texel is left alone.
#include "recon/hole_fill.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <vector>

namespace lidarscout::recon {
namespace {

TEST(HoleFill, InterpolatesTheWantedHolesOnly) {
    constexpr int n = 32;
    std::vector<float> h(n * n);
    std::vector<bool> wanted(h.size(), false);
    for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i) h[j * n + i] = 50.0f + 0.5f * i + 0.25f * j;  // a tilted plane
    const auto plane = h;
    for (int j = 10; j < 16; ++j)
        for (int i = 12; i < 18; ++i) h[j * n + i] = NAN, wanted[j * n + i] = true;  // a roof's hole
    h[0] = NAN;  // a hole not asked for
    hole_fill(h, n, wanted);
    EXPECT_TRUE(std::isnan(h[0]));
    float worst = 0;
    for (std::size_t t = 1; t < h.size(); ++t) worst = std::max(worst, std::abs(h[t] - plane[t]));
    std::printf("hole fill on a plane: worst error %.3f m over a 6 x 6 hole (slope 0.5 per texel)\n", worst);
    EXPECT_LT(worst, 1.0f) << "within two texels' rise of the plane";
    std::vector<float> empty(16, NAN);
    hole_fill(empty, 4, std::vector<bool>(16, true));
    EXPECT_TRUE(std::isnan(empty[5])) << "nothing to interpolate from";
}

}  // namespace
}  // namespace lidarscout::recon
