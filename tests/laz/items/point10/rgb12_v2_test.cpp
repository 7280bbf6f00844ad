// RGB12 v2: grey and coloured colours, repeated and changed in single bytes or whole
// channels, come back unchanged through the item's encoder and decoder.
#include "laz/items/point10/rgb12_v2.hpp"

#include <gtest/gtest.h>

#include <random>
#include <vector>

#include "laz/items/item_round_trip.hpp"

namespace lidarscout::laz::detail::point10 {
namespace {

TEST(Rgb12V2, ItemsRoundTrip) {
    constexpr std::size_t kSize = Rgb12StateV2::kSize;
    std::mt19937 rng(12);
    std::vector<std::uint8_t> items(kSize * 4000);
    for (std::size_t i = kSize; i < items.size(); i += kSize) {
        std::uint8_t* c = &items[i];
        for (std::size_t b = 0; b < kSize; ++b) c[b] = test::sticky<std::uint8_t>(rng, c[b - kSize], 0.7, 0, 255);
        if (rng() % 3 == 0) {  // grey: green and blue copy red
            c[2] = c[4] = c[0];
            c[3] = c[5] = c[1];
        }
    }
    EXPECT_EQ(test::item_round_trip(items, kSize, Rgb12EncoderV2(), Rgb12DecoderV2()), items);
}

}  // namespace
}  // namespace lidarscout::laz::detail::point10
