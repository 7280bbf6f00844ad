// radix_sort: the same order as std::stable_sort by the key, for keys of every width, shared
// digits skipped, equal keys kept in their order.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <vector>

#include "core/radix_sort.hpp"
#include "core/random.hpp"

namespace lidarscout {
namespace {

struct Item {
    std::uint64_t key;
    std::uint32_t order;  // the position before sorting
    bool operator==(const Item&) const = default;
};

std::vector<Item> random_items(std::size_t n, int key_bits, std::uint64_t seed, std::uint64_t shared_high = 0) {
    Rng random(seed);
    std::vector<Item> out(n);
    const std::uint64_t mask = key_bits >= 64 ? ~0ull : (1ull << key_bits) - 1;
    for (std::size_t i = 0; i < n; ++i) {
        std::uint64_t k = random.next() & mask;
        if (shared_high) k = (k & 0xff) | shared_high;  // only the low digit varies
        out[i] = {k, static_cast<std::uint32_t>(i)};
    }
    return out;
}

void expect_stably_sorted(std::vector<Item> items, int key_bits) {
    std::vector<Item> expected = items;
    std::stable_sort(expected.begin(), expected.end(), [](const Item& a, const Item& b) { return a.key < b.key; });
    radix_sort(items, [](const Item& i) { return i.key; }, key_bits);
    EXPECT_EQ(items, expected) << key_bits << " bits";
}

TEST(RadixSort, OrdersAsAStableSortByTheKey) {
    for (const int bits : {1, 8, 11, 12, 22, 32, 52, 64}) {
        expect_stably_sorted(random_items(5000, bits, 7 + bits), bits);
    }
    expect_stably_sorted(random_items(5000, 52, 3, 0x5a5a5a5a00ull), 52);  // high digits shared by all
    expect_stably_sorted(random_items(5000, 3, 4), 3);                     // many equal keys
}

TEST(RadixSort, EmptyAndSingleItems) {
    expect_stably_sorted({}, 32);
    expect_stably_sorted({{42, 0}}, 32);
    std::vector<std::uint64_t> codes{5, 3, 9, 3};
    radix_sort(codes, [](std::uint64_t c) { return c; }, 0);  // no key bits: nothing to order by
    EXPECT_EQ(codes, (std::vector<std::uint64_t>{5, 3, 9, 3}));
}

}  // namespace
}  // namespace lidarscout
