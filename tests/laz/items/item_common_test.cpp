// The item coders' shared building blocks: the GPS time delta multiple is rounded as LASzip
// rounds it, a delta fits in 32 bits or is refused, and the running median of five follows
// the LAZ window.
#include "laz/items/item_common.hpp"

#include <gtest/gtest.h>

#include <cstdint>
#include <limits>

namespace lidarscout::laz::detail {
namespace {

TEST(ItemCommon, GpsMultipleIsRoundedAsLaszipDoes) {
    EXPECT_EQ(gps_delta_multiple(20, 10), 2);
    EXPECT_EQ(gps_delta_multiple(15, 10), 2);  // 1.5 rounds away from zero
    EXPECT_EQ(gps_delta_multiple(-15, 10), -2);
    EXPECT_EQ(gps_delta_multiple(14, 10), 1);
    EXPECT_EQ(gps_delta_multiple(4, 10), 0);
    EXPECT_EQ(gps_delta_multiple(-5, 10), -1);
    // 16777217 / 2 is 8388608.5 exactly, but single precision makes it 8388608 first.
    EXPECT_EQ(gps_delta_multiple(16777217, 2), 8388608);
    // Quotients beyond int32 give INT32_MIN (x86-64 conversion of LASzip's rounding).
    constexpr auto kMin = std::numeric_limits<std::int32_t>::min();
    EXPECT_EQ(gps_delta_multiple(std::numeric_limits<std::int32_t>::max(), 1), kMin);
    EXPECT_EQ(gps_delta_multiple(kMin, -1), kMin);
    EXPECT_EQ(gps_delta_multiple(kMin, 1), kMin);
}

TEST(ItemCommon, GpsDeltaFitsInt32OrIsRefused) {
    EXPECT_EQ(gps_delta_as_int32(5), 5);
    EXPECT_EQ(gps_delta_as_int32(static_cast<std::uint64_t>(-7)), -7);
    EXPECT_EQ(gps_delta_as_int32(0x7FFFFFFFull), 0x7FFFFFFF);
    EXPECT_FALSE(gps_delta_as_int32(0x80000000ull).has_value());
    EXPECT_EQ(gps_delta_as_int32(static_cast<std::uint64_t>(-0x80000000ll)), std::numeric_limits<std::int32_t>::min());
    EXPECT_FALSE(gps_delta_as_int32(static_cast<std::uint64_t>(-0x80000001ll)).has_value());
}

TEST(ItemCommon, RunningMedianFollowsTheLazWindow) {
    RunningMedian5 m;
    EXPECT_EQ(m.median(), 0);  // starts as five zeros
    // 1 .. 4 evict alternately from the top and the bottom: {0,0,0,0,1} .. {0,1,2,3,4}.
    const std::int32_t expected[] = {0, 0, 1, 2};
    for (std::int32_t v = 1; v <= 4; ++v) {
        m.add(v);
        EXPECT_EQ(m.median(), expected[v - 1]) << "after adding " << v;
    }
    for (int i = 0; i < 5; ++i) m.add(-9);
    EXPECT_EQ(m.median(), -9);
    m.reset();
    EXPECT_EQ(m.median(), 0);
}

TEST(ItemCommon, ByteArithmeticWrapsAndClamps) {
    EXPECT_EQ(wrap_byte(256 + 3), 3);
    EXPECT_EQ(wrap_byte(-1), 255);
    EXPECT_EQ(clamp_byte(-4), 0);
    EXPECT_EQ(clamp_byte(300), 255);
    EXPECT_EQ(clamp_byte(77), 77);
    EXPECT_EQ(add_wrapping(std::numeric_limits<std::int32_t>::max(), 1), std::numeric_limits<std::int32_t>::min());
}

}  // namespace
}  // namespace lidarscout::laz::detail
