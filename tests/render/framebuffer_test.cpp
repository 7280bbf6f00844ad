// Framebuffer: packing, the atomic min (nearest wins in any order and under many threads) and
// size checks.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <random>
#include <thread>
#include <vector>

#include "core/error.hpp"
#include "render/framebuffer.hpp"

namespace lidarscout::render {
namespace {

TEST(RenderFramebuffer, PackedFragmentsRoundTripAndOrderByDepth) {
    const std::uint32_t rgba = pack_rgba(10, 20, 30, 40);
    EXPECT_EQ(red(rgba), 10);
    EXPECT_EQ(green(rgba), 20);
    EXPECT_EQ(blue(rgba), 30);
    EXPECT_EQ(alpha(rgba), 40);
    const std::uint64_t v = pack_fragment(123.25f, rgba);
    EXPECT_EQ(fragment_depth(v), 123.25f);
    EXPECT_EQ(fragment_rgba(v), rgba);
    // Depth decides before colour, and any depth is nearer than an empty pixel.
    EXPECT_LT(pack_fragment(1.0f, 0xffffffffu), pack_fragment(1.0001f, 0u));
    EXPECT_LT(pack_fragment(1e30f, 0xffffffffu), kEmpty);
}

TEST(RenderFramebuffer, WriteKeepsTheNearestInAnyOrder) {
    Framebuffer fb(4, 3);
    for (int y = 0; y < 3; ++y)
        for (int x = 0; x < 4; ++x) EXPECT_TRUE(fb.empty_at(x, y));
    fb.write(1, 2, 50.0f, pack_rgba(255, 0, 0));
    fb.write(1, 2, 20.0f, pack_rgba(0, 255, 0));
    fb.write(1, 2, 70.0f, pack_rgba(0, 0, 255));
    EXPECT_EQ(fragment_rgba(fb.at(1, 2)), pack_rgba(0, 255, 0));
    EXPECT_EQ(fragment_depth(fb.at(1, 2)), 20.0f);
    EXPECT_TRUE(fb.empty_at(2, 1));
    fb.clear();
    EXPECT_TRUE(fb.empty_at(1, 2));
}

TEST(RenderFramebuffer, AtomicMinUnderManyThreads) {
    Framebuffer fb(2, 2);
    constexpr int kThreads = 8, kWrites = 100'000;
    std::vector<std::uint64_t> thread_min(kThreads, kEmpty);
    std::vector<std::thread> threads;
    for (int t = 0; t < kThreads; ++t) {
        threads.emplace_back([&, t] {
            std::mt19937 rng(1234 + t);
            std::uniform_real_distribution<float> depth(1.0f, 1000.0f);
            for (int i = 0; i < kWrites; ++i) {
                const std::uint64_t v = pack_fragment(depth(rng), static_cast<std::uint32_t>(rng()));
                fb.write_packed(i % 2, 1, v);  // all threads race on the same two pixels
                if (i % 2 == 0) thread_min[t] = std::min(thread_min[t], v);
            }
        });
    }
    for (auto& th : threads) th.join();
    EXPECT_EQ(fb.at(0, 1), *std::min_element(thread_min.begin(), thread_min.end()));
    EXPECT_LT(fb.at(1, 1), kEmpty);
    EXPECT_TRUE(fb.empty_at(0, 0));
}

TEST(RenderFramebuffer, RejectsBadSizes) {
    EXPECT_THROW(Framebuffer(0, 10), Error);
    EXPECT_THROW(Framebuffer(10, -1), Error);
    EXPECT_THROW(Framebuffer(40000, 10), Error);
    const Framebuffer fb(8, 6);
    EXPECT_NO_THROW(fb.check_size(8, 6, "test"));
    EXPECT_THROW(fb.check_size(6, 8, "test"), Error);
}

}  // namespace
}  // namespace lidarscout::render
