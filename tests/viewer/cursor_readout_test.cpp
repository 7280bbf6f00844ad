// The cursor readout: the ground point under a pixel is the one that projects to that pixel
// (the inverse of Camera::project), and its longitude/latitude where the CRS is known.
#include <gtest/gtest.h>

#include "render/camera.hpp"
#include "viewer/cursor_readout.hpp"

namespace lidarscout::viewer {
namespace {

TEST(CursorReadout, GroundUnderPixelInvertsProject) {
    const render::Camera cam = render::parse_camera("1000,2000,500,30,-50", 800, 600, 60);
    for (const auto& [gx, gy] : {std::pair{1100.0, 2300.0}, std::pair{900.0, 2600.0}, std::pair{1250.0, 2150.0}}) {
        const auto p = cam.project(gx, gy, 120.0);
        ASSERT_TRUE(p);
        const auto g = ground_under_pixel(cam, p->x, p->y, 120.0);
        ASSERT_TRUE(g);
        EXPECT_NEAR((*g)[0], gx, 0.05);
        EXPECT_NEAR((*g)[1], gy, 0.05);
    }
    const render::Camera level = render::parse_camera("1000,2000,500,30,-20", 800, 600, 60);
    EXPECT_FALSE(ground_under_pixel(level, 400, 0, 120.0));  // 20 degrees down with a 60 degree fov: the top row is sky
    EXPECT_TRUE(ground_under_pixel(level, 400, 599, 120.0));
}

TEST(CursorReadout, LonLatWhereTheCrsIsKnown) {
    // Kentucky Single Zone (US feet); the dataset's frame is in metres of it
    const dataset::Frame ky{"EPSG:3089", 1200.0 / 3937.0, 1200.0 / 3937.0};
    const CursorReadout readout(ky);
    ASSERT_TRUE(readout.has_lonlat());
    const auto ll = readout.lonlat(5'690'000 * ky.xy_to_metres, 3'900'000 * ky.xy_to_metres);
    ASSERT_TRUE(ll);
    EXPECT_GT((*ll)[0], -84.5);
    EXPECT_LT((*ll)[0], -82.0);
    EXPECT_GT((*ll)[1], 37.0);
    EXPECT_LT((*ll)[1], 38.5);
    const render::Camera cam = render::parse_camera("1734000,1188000,3000,0,-60", 800, 600, 60);
    EXPECT_NE(readout.text(cam, 400, 300, 300).find("lon -8"), std::string::npos);
    const CursorReadout none(dataset::Frame{});
    EXPECT_FALSE(none.has_lonlat());
    EXPECT_EQ(none.text(cam, 400, 300, 300).find("lon"), std::string::npos);
    EXPECT_NE(none.text(cam, 400, 300, 300).find(" m"), std::string::npos);
}

}  // namespace
}  // namespace lidarscout::viewer
