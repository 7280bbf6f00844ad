// GPSTIME11 v2: times with regular steps, repeats, multiples of the last step, negative
// steps, jumps beyond 32 bits and two interleaved sequences (the switch symbols) come back
// unchanged through the item's encoder and decoder.
#include "laz/items/point10/gpstime11_v2.hpp"

#include <gtest/gtest.h>

#include <cstring>
#include <random>
#include <vector>

#include "laz/items/item_round_trip.hpp"

namespace lidarscout::laz::detail::point10 {
namespace {

TEST(GpsTime11V2, ItemsRoundTrip) {
    constexpr std::size_t kSize = GpsTime11EncoderV2::kSize;
    std::mt19937 rng(11);
    // Two scanners: times (as bit patterns) around two far-apart bases.
    std::uint64_t scanner[2] = {0x41D0000000000000ull, 0x41E0000000000000ull};
    std::vector<std::uint8_t> items;
    for (int i = 0; i < 6000; ++i) {
        std::uint64_t& t = scanner[(i / 50) % 2 == 1 && i % 2 ? 1 : 0];
        switch (rng() % 8) {
            case 0: break;                                          // unchanged
            case 1: t += 1000 * (1 + rng() % 600); break;           // a (large) multiple
            case 2: t -= 1000 * (1 + rng() % 12); break;            // a negative multiple
            case 3: if (rng() % 20 == 0) t += 1ull << 40; break;    // a jump: a new sequence
            default: t += 1000 + rng() % 5; break;                  // the regular step
        }
        std::uint8_t b[kSize];
        std::memcpy(b, &t, kSize);
        items.insert(items.end(), b, b + kSize);
    }
    EXPECT_EQ(test::item_round_trip(items, kSize, GpsTime11EncoderV2(), GpsTime11DecoderV2()), items);
}

}  // namespace
}  // namespace lidarscout::laz::detail::point10
