// looks_like_degrees on boxes in degrees and in metres; utm_zone_at against zones read off the
// EPSG registry (Autzen in zone 10N, Sydney in 56S, the zone edges at 180 W / 180 E).
#include <gtest/gtest.h>

#include "geo/geographic.hpp"

namespace lidarscout::geo {
namespace {

TEST(Geographic, LooksLikeDegrees) {
    EXPECT_TRUE(looks_like_degrees(-84.75, 38.04, -84.70, 38.08));
    EXPECT_TRUE(looks_like_degrees(0, -90, 360, 90));
    EXPECT_FALSE(looks_like_degrees(173036, 5623082, 173241, 5623390));
    EXPECT_FALSE(looks_like_degrees(10, 91, 11, 92));  // y past the pole
}

TEST(Geographic, UtmZoneAt) {
    EXPECT_EQ(utm_zone_at(-123.07, 44.05).crs, "EPSG:32610");  // Autzen, Oregon
    EXPECT_EQ(utm_zone_at(-123.07, 44.05).name, "WGS 84 / UTM zone 10N");
    EXPECT_EQ(utm_zone_at(151.2, -33.9).crs, "EPSG:32756");  // Sydney
    EXPECT_EQ(utm_zone_at(3.0, 0.0).crs, "EPSG:32631");
    EXPECT_EQ(utm_zone_at(-180.0, 10).crs, "EPSG:32601");
    EXPECT_EQ(utm_zone_at(179.99, 10).crs, "EPSG:32660");
    EXPECT_EQ(utm_zone_at(180.0, 10).crs, "EPSG:32601");  // 180 E is 180 W
    EXPECT_EQ(utm_zone_at(-84.7, 38.0).crs, "EPSG:32616");  // Kentucky
}

}  // namespace
}  // namespace lidarscout::geo
