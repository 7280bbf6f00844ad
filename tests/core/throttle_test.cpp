// Throttle: small work is always due; long work once per interval after it was done.
#include <gtest/gtest.h>

#include "core/throttle.hpp"

namespace lidarscout {
namespace {

using namespace std::chrono_literals;

TEST(Throttle, SmallWorkIsAlwaysDueLongWorkOncePerInterval) {
    Throttle t(200ms, 10);
    const auto t0 = Throttle::Clock::now();
    EXPECT_TRUE(t.due(1000, t0)) << "never done: due";
    t.done(t0);
    EXPECT_TRUE(t.due(10, t0 + 1ms));
    EXPECT_FALSE(t.due(11, t0 + 1ms));
    EXPECT_FALSE(t.due(1000, t0 + 199ms));
    EXPECT_TRUE(t.due(1000, t0 + 200ms));
    t.done(t0 + 250ms);
    EXPECT_FALSE(t.due(1000, t0 + 300ms));
}

}  // namespace
}  // namespace lidarscout
