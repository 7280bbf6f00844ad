// POINT10 v2: records with wandering XYZ, changing returns (well-formed and out of spec),
// intensity, classification, scan angle, user data and point source come back unchanged
// through the item's encoder and decoder.
#include "laz/items/point10/point10_v2.hpp"

#include <gtest/gtest.h>

#include <random>
#include <vector>

#include "laz/items/item_round_trip.hpp"

namespace lidarscout::laz::detail::point10 {
namespace {

TEST(Point10V2, ItemsRoundTrip) {
    std::mt19937 rng(10);
    std::vector<std::uint8_t> items(kPoint10Size);
    Point10Record p = Point10Record::load(items.data());
    for (int i = 1; i < 5000; ++i) {
        p.x += static_cast<std::int32_t>(rng() % 2001) - 1000;
        p.y += static_cast<std::int32_t>(rng() % 201) - 100;
        p.z = rng() % 50 == 0 ? static_cast<std::int32_t>(rng()) : p.z + static_cast<std::int32_t>(rng() % 21) - 10;
        p.return_flags = test::sticky<std::uint8_t>(rng, p.return_flags, 0.5, 0, 255);
        p.intensity = test::sticky<std::uint16_t>(rng, p.intensity, 0.3, 0, 65535);
        p.classification = test::sticky<std::uint8_t>(rng, p.classification, 0.9, 0, 31);
        p.scan_angle = test::sticky<std::uint8_t>(rng, p.scan_angle, 0.8, 0, 255);
        p.user_data = test::sticky<std::uint8_t>(rng, p.user_data, 0.95, 0, 255);
        p.point_source = test::sticky<std::uint16_t>(rng, p.point_source, 0.97, 0, 65535);
        items.resize(items.size() + kPoint10Size);
        p.store(items.data() + items.size() - kPoint10Size);
    }
    EXPECT_EQ(test::item_round_trip(items, kPoint10Size, Point10EncoderV2(), Point10DecoderV2()), items);
}

}  // namespace
}  // namespace lidarscout::laz::detail::point10
