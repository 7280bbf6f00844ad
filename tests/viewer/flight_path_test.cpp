// The scripted flight: from 20% to 80% of the dataset's diagonal while the height falls from
// the start to the end height above its top, with t clamped to [0, 1].
#include "viewer/flight_path.hpp"

#include <gtest/gtest.h>

namespace lidarscout::viewer {
namespace {

TEST(ViewerFlightPath, GoesAlongTheDiagonalAndDown) {
    dataset::Bounds b;
    b.min_x = 1000, b.max_x = 2000, b.min_y = 5000, b.max_y = 7000, b.min_z = 10, b.max_z = 110;
    FlightPath path;
    path.start_height_m = 1000, path.end_height_m = 100, path.width = 640, path.height = 480;
    const auto start = flight_camera(b, 0, path), middle = flight_camera(b, 0.5, path), end = flight_camera(b, 1, path);
    EXPECT_DOUBLE_EQ(start.x, 1200);
    EXPECT_DOUBLE_EQ(start.y, 5400);
    EXPECT_DOUBLE_EQ(start.z, 1110);
    EXPECT_DOUBLE_EQ(middle.x, 1500);
    EXPECT_DOUBLE_EQ(middle.z, 660);
    EXPECT_DOUBLE_EQ(end.x, 1800);
    EXPECT_DOUBLE_EQ(end.y, 6600);
    EXPECT_DOUBLE_EQ(end.z, 210);
    EXPECT_EQ(end.width, 640);
    EXPECT_EQ(end.yaw_deg, path.yaw_deg);
    EXPECT_EQ(end.pitch_deg, path.pitch_deg);
    EXPECT_DOUBLE_EQ(flight_camera(b, 2, path).x, end.x);    // clamped
    EXPECT_DOUBLE_EQ(flight_camera(b, -1, path).z, start.z);
}

}  // namespace
}  // namespace lidarscout::viewer
