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

}  // namespace
}  // namespace lidarscout::test
