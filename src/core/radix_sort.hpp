// A stable least-significant-digit radix sort of a vector by an unsigned integer key of at most 64
// bits: 11-bit digits, all digit counts taken in one pass, and a digit that every element shares
// skipped. For the large sorts by grid position (patch points, level-of-detail codes), where it
// is several times faster than std::sort.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

namespace lidarscout {

// Sorts `items` by `key(item)` (a std::uint64_t below 2^key_bits), keeping the order of equal keys.
template <class T, class KeyOf>
void radix_sort(std::vector<T>& items, KeyOf key, int key_bits) {
    constexpr int kDigitBits = 11;
    constexpr std::size_t kBuckets = std::size_t{1} << kDigitBits;
    const int digits = (key_bits + kDigitBits - 1) / kDigitBits;
    if (items.size() < 2 || digits == 0) return;
    std::vector<std::array<std::size_t, kBuckets>> start(static_cast<std::size_t>(digits));
    for (auto& s : start) s.fill(0);
    for (const T& item : items) {
        const std::uint64_t k = key(item);
        for (int d = 0; d < digits; ++d) ++start[d][(k >> (d * kDigitBits)) & (kBuckets - 1)];
    }
    std::vector<T> other(items.size());
    for (int d = 0; d < digits; ++d) {
        auto& s = start[d];
        bool shared = false;
        std::size_t sum = 0;
        for (std::size_t b = 0; b < kBuckets; ++b) {
            shared = shared || s[b] == items.size();
            const std::size_t count = s[b];
            s[b] = sum, sum += count;
        }
        if (shared) continue;
        for (const T& item : items) other[s[(key(item) >> (d * kDigitBits)) & (kBuckets - 1)]++] = item;
        items.swap(other);
    }
}

}  // namespace lidarscout
