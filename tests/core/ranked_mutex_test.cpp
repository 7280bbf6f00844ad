// The ranked mutex: locks taken in rank order (and again after release, and through a condition
// variable's wait) pass; a lower or equal rank taken under a higher one stops the process with
// both names.
#include "core/ranked_mutex.hpp"

#include <gtest/gtest.h>

#include <chrono>
#include <condition_variable>
#include <mutex>

namespace lidarscout {
namespace {

TEST(RankedMutex, InOrderPasses) {
    RankedMutex low(1, "low"), high(2, "high");
    {
        std::lock_guard a(low);
        std::lock_guard b(high);
    }
    {
        std::unique_lock b(high);  // alone: any rank
        b.unlock();
        std::lock_guard a(low);  // high is no longer held
    }
    std::unique_lock a(low);
    EXPECT_TRUE(high.try_lock());
    high.unlock();
    EXPECT_TRUE(a.owns_lock());
}

TEST(RankedMutex, WaitReleasesAndRetakes) {
    RankedMutex low(1, "low"), high(2, "high");
    std::condition_variable_any cv;
    std::unique_lock a(low);
    cv.wait_for(a, std::chrono::milliseconds(1));
    std::lock_guard b(high);  // low held again after the wait, high above it: in order
    SUCCEED();
}

// Takes `second` while holding `first`.
void nest(RankedMutex& first, RankedMutex& second) {
    std::lock_guard a(first);
    std::lock_guard b(second);
}

TEST(RankedMutexDeathTest, OutOfOrderStops) {
    RankedMutex residency(1, "residency");
    RankedMutex state(2, "scheduler state");
    RankedMutex one(3, "one");
    RankedMutex other(3, "other");
    EXPECT_DEATH(nest(state, residency),
                 "lock order broken: taking \"residency\" \\(rank 1\\) while holding \"scheduler state\" "
                 "\\(rank 2\\)");
    EXPECT_DEATH(nest(one, other), "lock order broken");
}

}  // namespace
}  // namespace lidarscout
