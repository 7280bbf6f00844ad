// grid_geometry.hpp's circumcircle: its centre and radius against a triangle with a known circle,
// grown only by the stated slack, and circle_within on either side of its bound.
#include "recon/grid_geometry.hpp"

#include <gtest/gtest.h>

#include <cmath>

namespace lidarscout::recon {
namespace {

TEST(GridGeometry, TheCircumcircleIsTheCircleThroughTheCorners) {
    // a right triangle: its circle's centre is the hypotenuse's midpoint
    const Circle c = circumcircle({1000, 2000}, {1600, 2000}, {1000, 2800});
    EXPECT_DOUBLE_EQ(c.x, 1300);
    EXPECT_DOUBLE_EQ(c.y, 2400);
    EXPECT_NEAR(c.radius, 500 * (1 + 1e-9) + 4, 1e-9);  // 500, grown by its slack
    // large coordinates (near 2^25) and a thin triangle: still through all three corners
    const GridXY a{33000000, 100}, b{33554000, 130}, d{33277000, 900};
    const Circle t = circumcircle(a, b, d);
    for (const GridXY& p : {a, b, d}) {
        EXPECT_NEAR(std::hypot(p.x - t.x, p.y - t.y), t.radius - 4, 1e-3 * t.radius) << p.x;
        EXPECT_LT(std::hypot(p.x - t.x, p.y - t.y), t.radius);
    }
}

TEST(GridGeometry, ACircleIsWithinAReachOnlyWhollyInside) {
    const Circle c{100, 0, 50};
    EXPECT_TRUE(circle_within(c, {0, 0}, 151));
    EXPECT_FALSE(circle_within(c, {0, 0}, 150));  // touching the rim is not within
    EXPECT_FALSE(circle_within(c, {0, 0}, 120));
    EXPECT_TRUE(circle_within(c, {100, 0}, 50.01));
}

}  // namespace
}  // namespace lidarscout::recon
