// Camera: projection of known points (double path and the float screen transform), the
// clip-space matrix, the auto camera and parse_camera's errors.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "core/error.hpp"
#include "render/camera.hpp"

namespace lidarscout::render {
namespace {

// A camera at survey-sized coordinates, looking north, level.
Camera level_camera() {
    Camera c;
    c.x = 712'345.25;
    c.y = 4'123'456.75;
    c.z = 312.5;
    c.width = 640;
    c.height = 480;
    return c;
}

TEST(RenderCamera, PointStraightAheadProjectsToTheCentre) {
    const Camera c = level_camera();
    const auto p = c.project(c.x, c.y + 100.0, c.z);
    ASSERT_TRUE(p.has_value());
    EXPECT_NEAR(p->x, 320.0f, 1e-3);
    EXPECT_NEAR(p->y, 240.0f, 1e-3);
    EXPECT_NEAR(p->depth, 100.0f, 1e-3);
}

TEST(RenderCamera, LateralOffsetsFollowTheFocalLength) {
    const Camera c = level_camera();
    const double f = 240.0 / std::tan(30.0 * 3.14159265358979 / 180.0);
    EXPECT_NEAR(c.focal_px(), f, 1e-9);
    // 10 m east at 100 m ahead: right of centre; 10 m up: above centre (rows grow down).
    const auto east = c.project(c.x + 10.0, c.y + 100.0, c.z);
    const auto up = c.project(c.x, c.y + 100.0, c.z + 10.0);
    ASSERT_TRUE(east && up);
    EXPECT_NEAR(east->x, 320.0 + 0.1 * f, 1e-3);
    EXPECT_NEAR(east->y, 240.0, 1e-3);
    EXPECT_NEAR(up->y, 240.0 - 0.1 * f, 1e-3);
    // At tan(fov / 2) * depth above the axis a point lies on the top edge.
    const auto top = c.project(c.x, c.y + 100.0, c.z + 100.0 * std::tan(30.0 * 3.14159265358979 / 180.0));
    ASSERT_TRUE(top);
    EXPECT_NEAR(top->y, 0.0, 1e-3);
}

TEST(RenderCamera, YawAndPitchTurnTheView) {
    Camera c = level_camera();
    c.yaw_deg = 90;  // east
    const auto ahead = c.project(c.x + 50.0, c.y, c.z);
    const auto north = c.project(c.x + 50.0, c.y + 10.0, c.z);
    ASSERT_TRUE(ahead && north);
    EXPECT_NEAR(ahead->x, 320.0, 1e-3);
    EXPECT_LT(north->x, 310.0f);  // looking east, north is on the left
    EXPECT_FALSE(c.project(c.x, c.y + 50.0, c.z).has_value());  // due north is beside the camera

    c.yaw_deg = 0;
    c.pitch_deg = -90;  // straight down, north at the top of the image
    const auto below = c.project(c.x, c.y, c.z - 200.0);
    const auto below_north = c.project(c.x, c.y + 20.0, c.z - 200.0);
    const auto below_east = c.project(c.x + 20.0, c.y, c.z - 200.0);
    ASSERT_TRUE(below && below_north && below_east);
    EXPECT_NEAR(below->x, 320.0, 1e-3);
    EXPECT_NEAR(below->y, 240.0, 1e-3);
    EXPECT_NEAR(below->depth, 200.0, 1e-3);
    EXPECT_LT(below_north->y, 230.0f);
    EXPECT_GT(below_east->x, 330.0f);
}

TEST(RenderCamera, PointsBehindOrOutsideTheDepthRangeAreRejected) {
    Camera c = level_camera();
    c.near_m = 1.0;
    c.far_m = 1000.0;
    EXPECT_FALSE(c.project(c.x, c.y - 10.0, c.z).has_value());
    EXPECT_FALSE(c.project(c.x, c.y + 0.5, c.z).has_value());
    EXPECT_FALSE(c.project(c.x, c.y + 1000.5, c.z).has_value());
    EXPECT_TRUE(c.project(c.x, c.y + 999.0, c.z).has_value());
}

TEST(RenderCamera, ScreenTransformMatchesProjectFarFromTheOrigin) {
    Camera c = level_camera();
    c.yaw_deg = 33;
    c.pitch_deg = -41;
    // Points stored as float offsets from a batch origin 2 km away from the camera.
    const double ox = c.x + 1500.0, oy = c.y + 1400.0, oz = 100.0;
    const ScreenTransform s = c.screen_transform(ox, oy, oz);
    for (const auto& d : {std::array<float, 3>{0, 0, 0}, {123.25f, -45.5f, 7.0f}, {-300.0f, 250.0f, -20.0f}}) {
        const auto p = c.project(ox + d[0], oy + d[1], oz + d[2]);
        ASSERT_TRUE(p);
        const float w = s.depth[0] * d[0] + s.depth[1] * d[1] + s.depth[2] * d[2] + s.depth[3];
        const float x = (s.sx[0] * d[0] + s.sx[1] * d[1] + s.sx[2] * d[2] + s.sx[3]) / w;
        const float y = (s.sy[0] * d[0] + s.sy[1] * d[1] + s.sy[2] * d[2] + s.sy[3]) / w;
        EXPECT_NEAR(w, p->depth, 1e-3 * p->depth);
        EXPECT_NEAR(x, p->x, 0.01);
        EXPECT_NEAR(y, p->y, 0.01);
    }
}

TEST(RenderCamera, ViewProjectionGivesNdcOfTheProjectedPixel) {
    Camera c = level_camera();
    c.yaw_deg = -20;
    c.pitch_deg = -15;
    c.near_m = 2.0;
    c.far_m = 5000.0;
    const Mat4 m = c.view_projection();
    const double v[3] = {40.0, 300.0, -60.0};  // relative to the camera
    const auto p = c.project(c.x + v[0], c.y + v[1], c.z + v[2]);
    ASSERT_TRUE(p);
    float clip[4];
    for (int r = 0; r < 4; ++r) clip[r] = m(r, 0) * v[0] + m(r, 1) * v[1] + m(r, 2) * v[2] + m(r, 3);
    EXPECT_NEAR(clip[3], p->depth, 1e-3);
    EXPECT_NEAR(clip[0] / clip[3], 2.0 * p->x / c.width - 1.0, 1e-4);
    EXPECT_NEAR(clip[1] / clip[3], 1.0 - 2.0 * p->y / c.height, 1e-4);
    // Clip z / w runs from -1 at the near plane to +1 at the far plane.
    const auto ndc_z = [&](double depth) {
        const auto f = c.basis().forward;
        float z = m(2, 3), w = m(3, 3);
        for (int k = 0; k < 3; ++k) z += m(2, k) * f[k] * depth, w += m(3, k) * f[k] * depth;
        return z / w;
    };
    EXPECT_NEAR(ndc_z(2.0), -1.0, 1e-4);
    EXPECT_NEAR(ndc_z(5000.0), 1.0, 1e-4);
}

TEST(RenderCamera, AutoCameraSeesTheWholeBoxFromTheSouth) {
    const double lo[3] = {500'000, 4'000'000, 120}, hi[3] = {540'000, 4'025'000, 900};
    const Camera c = Camera::looking_at_bounds(lo[0], lo[1], lo[2], hi[0], hi[1], hi[2], 1280, 720);
    EXPECT_EQ(c.width, 1280);
    EXPECT_EQ(c.height, 720);
    EXPECT_LE(c.pitch_deg, -60.0);
    EXPECT_GE(c.pitch_deg, -90.0);
    EXPECT_LT(c.y, 0.5 * (lo[1] + hi[1]));  // south of the centre, looking north
    EXPECT_GT(c.z, hi[2]);
    double widest = 0;  // the largest |NDC| of a corner: the box fills the view
    for (int corner = 0; corner < 8; ++corner) {
        const auto p =
            c.project((corner & 1) ? hi[0] : lo[0], (corner & 2) ? hi[1] : lo[1], (corner & 4) ? hi[2] : lo[2]);
        ASSERT_TRUE(p) << corner;
        EXPECT_GE(p->x, 0.0f);
        EXPECT_LE(p->x, 1280.0f);
        EXPECT_GE(p->y, 0.0f);
        EXPECT_LE(p->y, 720.0f);
        widest = std::max({widest, std::abs(p->x / 640.0 - 1.0), std::abs(p->y / 360.0 - 1.0)});
    }
    EXPECT_NEAR(widest, 0.95, 0.01);
    const auto centre = c.project(0.5 * (lo[0] + hi[0]), 0.5 * (lo[1] + hi[1]), 0.5 * (lo[2] + hi[2]));
    ASSERT_TRUE(centre);
    EXPECT_NEAR(centre->x, 640.0, 0.5);
    EXPECT_NEAR(centre->y, 360.0, 0.5);
}

TEST(RenderCamera, ParseCameraReadsFiveNumbers) {
    const Camera c = parse_camera("712345.5, 4123456.25,300,45,-30", 800, 600, 50);
    EXPECT_DOUBLE_EQ(c.x, 712345.5);
    EXPECT_DOUBLE_EQ(c.y, 4123456.25);
    EXPECT_DOUBLE_EQ(c.z, 300);
    EXPECT_DOUBLE_EQ(c.yaw_deg, 45);
    EXPECT_DOUBLE_EQ(c.pitch_deg, -30);
    EXPECT_EQ(c.width, 800);
    EXPECT_EQ(c.height, 600);
    EXPECT_DOUBLE_EQ(c.fov_deg, 50);
}

TEST(RenderCamera, ParseCameraRejectsBadText) {
    for (const char* bad : {"", "1,2,3,4", "1,2,3,4,5,6", "1,2,x,4,5", "1,2,3,4,", "1,,3,4,5", "1,2,3,4,5m",
                            "nan,2,3,4,5", "1,2,inf,4,5", "1,2,3,4,-90.5", "1,2,3,4,91"}) {
        EXPECT_THROW(parse_camera(bad), Error) << bad;
    }
    try {
        parse_camera("1,2,3,4");
        FAIL();
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find("X,Y,Z,YAW,PITCH"), std::string::npos) << e.what();
    }
}

}  // namespace
}  // namespace lidarscout::render
