// ThreadPool: every index runs exactly once, errors propagate, nesting does not dead-lock, and no
// request starts more than max_threads() threads.
#include <gtest/gtest.h>

#include <atomic>
#include <fstream>
#include <string>
#include <chrono>
#include <thread>
#include <stdexcept>
#include <vector>

#include "core/thread_pool.hpp"

namespace lidarscout {
namespace {

TEST(ThreadPool, EveryIndexOnce) {
    for (unsigned threads : {1u, 2u, 4u}) {
        ThreadPool pool(threads);
        EXPECT_EQ(pool.size(), threads);
        std::vector<std::atomic<int>> hits(10'000);
        pool.for_each(hits.size(), [&](std::size_t i) { hits[i]++; });
        for (const auto& h : hits) ASSERT_EQ(h.load(), 1);
    }
}

TEST(ThreadPool, FirstErrorIsRethrown) {
    ThreadPool pool(3);
    std::atomic<int> ran{0};
    // Every other iteration takes 200 us, so the whole range would need ~70 ms on 3 threads:
    // the error at index 10 (within the first ~1 ms) must stop the loop long before that,
    // even on a loaded machine or under a sanitizer.
    EXPECT_THROW(pool.for_each(1000, [&](std::size_t i) {
        ran++;
        if (i == 10) throw std::runtime_error("boom");
        std::this_thread::sleep_for(std::chrono::microseconds(200));
    }), std::runtime_error);
    EXPECT_LT(ran.load(), 1000);
    // The pool is still usable afterwards.
    std::atomic<int> after{0};
    pool.for_each(100, [&](std::size_t) { after++; });
    EXPECT_EQ(after.load(), 100);
}

TEST(ThreadPool, NestedLoops) {
    ThreadPool pool(2);
    std::atomic<int> total{0};
    pool.for_each(8, [&](std::size_t) { pool.for_each(8, [&](std::size_t) { total++; }); });
    EXPECT_EQ(total.load(), 64);
}

TEST(ThreadPool, EmptyLoop) {
    ThreadPool pool(2);
    pool.for_each(0, [](std::size_t) { FAIL(); });
}

// Threads of this process now (/proc/self/status).
std::size_t process_threads() {
    std::ifstream in("/proc/self/status");
    for (std::string key; in >> key;) {
        if (key == "Threads:") {
            std::size_t n = 0;
            in >> n;
            return n;
        }
    }
    return 0;
}

TEST(ThreadPool, HugeRequestIsCapped) {
    EXPECT_EQ(max_threads(), std::min(256u, 4 * std::max(1u, std::thread::hardware_concurrency())));
    EXPECT_EQ(capped_threads(0), 0u);
    EXPECT_EQ(capped_threads(100'000), max_threads());
    const std::size_t before = process_threads();
    ASSERT_GT(before, 0u);
    ThreadPool pool(100'000);
    EXPECT_EQ(pool.size(), max_threads());
    EXPECT_EQ(process_threads(), before + max_threads() - 1);  // the caller is one of them
    std::atomic<int> total{0};
    pool.for_each(1000, [&](std::size_t) { total++; });
    EXPECT_EQ(total.load(), 1000);
}

}  // namespace
}  // namespace lidarscout
