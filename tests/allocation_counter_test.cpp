// The allocation counter counts: what a block allocates while a counter lives, nothing before.
#include "allocation_counter.hpp"

#include <gtest/gtest.h>

#include <memory>
#include <vector>

namespace lidarscout::test {
namespace {

TEST(AllocationCounter, CountsWhatIsAllocatedWhileItLives) {
    auto before = std::make_unique<std::vector<char>>(1 << 20);  // not counted
    const AllocationCounter counter;
    EXPECT_LT(counter.bytes(), 1024u);
    std::vector<char> inside(3 << 20);
    asm volatile("" : : "g"(inside.data()) : "memory");  // (kept, not optimised away)
    EXPECT_GE(counter.bytes(), 3u << 20);
    EXPECT_LT(counter.bytes(), 4u << 20);
    before.reset();
}

TEST(AllocationCounter, PeakIsTheMostHeldAtOnce) {
    const AllocationCounter counter;
    for (int i = 0; i < 8; ++i) {
        std::vector<char> block(1 << 20);  // one MiB at a time, freed before the next
        asm volatile("" : : "g"(block.data()) : "memory");
    }
    EXPECT_GE(counter.bytes(), 8u << 20);
    EXPECT_GE(counter.peak_bytes(), 1u << 20);
    EXPECT_LT(counter.peak_bytes(), 2u << 20);
}

}  // namespace
}  // namespace lidarscout::test
