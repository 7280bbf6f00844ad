// BYTE v2 (extra bytes): items that repeat, change by a little and jump come back unchanged
// through the item's encoder and decoder, for 1 and 5 bytes per item.
#include "laz/items/point10/byte_v2.hpp"

#include <gtest/gtest.h>

#include <random>
#include <vector>

#include "laz/items/item_round_trip.hpp"

namespace lidarscout::laz::detail::point10 {
namespace {

TEST(ByteV2, ItemsRoundTrip) {
    for (const std::size_t size : {1u, 5u}) {
        std::mt19937 rng(static_cast<unsigned>(size));
        std::vector<std::uint8_t> items(size * 3000);
        for (std::size_t i = size; i < items.size(); ++i) {
            items[i] = test::sticky<std::uint8_t>(rng, items[i - size], 0.6, 0, 255);
        }
        EXPECT_EQ(test::item_round_trip(items, size, ByteEncoderV2(size), ByteDecoderV2(size)), items)
            << size << " bytes per item";
    }
}

}  // namespace
}  // namespace lidarscout::laz::detail::point10
