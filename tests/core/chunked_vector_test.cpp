// ChunkedVector: items in order across chunks, truncation within and across chunks, clear.
#include <gtest/gtest.h>

#include "core/chunked_vector.hpp"

namespace lidarscout {
namespace {

TEST(ChunkedVector, HoldsItemsInOrderAcrossChunks) {
    ChunkedVector<int, 4> v;
    EXPECT_TRUE(v.empty());
    for (int i = 0; i < 11; ++i) v.push_back(i * 10);
    ASSERT_EQ(v.size(), 11u);
    for (int i = 0; i < 11; ++i) EXPECT_EQ(v[i], i * 10);
    v[5] = -1;
    EXPECT_EQ(v[5], -1);
}

TEST(ChunkedVector, TruncatesAndKeepsAppending) {
    ChunkedVector<int, 4> v;
    for (int i = 0; i < 11; ++i) v.push_back(i);
    v.truncate(8);  // exactly two chunks
    ASSERT_EQ(v.size(), 8u);
    v.push_back(100);
    EXPECT_EQ(v[8], 100);
    v.truncate(3);  // within the first chunk
    ASSERT_EQ(v.size(), 3u);
    for (int i = 0; i < 6; ++i) v.push_back(50 + i);
    ASSERT_EQ(v.size(), 9u);
    const int expected[] = {0, 1, 2, 50, 51, 52, 53, 54, 55};
    for (int i = 0; i < 9; ++i) EXPECT_EQ(v[i], expected[i]) << i;
    v.truncate(20);  // more than it holds: nothing changes
    EXPECT_EQ(v.size(), 9u);
    v.truncate(0);
    EXPECT_TRUE(v.empty());
    v.push_back(7);
    EXPECT_EQ(v[0], 7);
    v.clear();
    EXPECT_EQ(v.size(), 0u);
}

}  // namespace
}  // namespace lidarscout
