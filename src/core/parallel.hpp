// parallel_for: run fn(i) for i in [0, n) on up to `threads` threads (dynamic scheduling).
// Exceptions are not propagated: fn must handle its own errors (store them per item).
#pragma once

#include <algorithm>
#include <atomic>
#include <cstddef>
#include <thread>
#include <vector>

namespace lidarscout {

inline unsigned default_thread_count() { return std::max(1u, std::thread::hardware_concurrency()); }

template <typename Fn>
void parallel_for(std::size_t n, unsigned threads, Fn&& fn) {
    threads = static_cast<unsigned>(std::min<std::size_t>(std::max(1u, threads), n));
    if (threads <= 1) {
        for (std::size_t i = 0; i < n; ++i) fn(i);
        return;
    }
    std::atomic<std::size_t> next{0};
    auto worker = [&] {
        for (std::size_t i; (i = next.fetch_add(1, std::memory_order_relaxed)) < n;) fn(i);
    };
    std::vector<std::jthread> pool;
    pool.reserve(threads - 1);
    for (unsigned t = 1; t < threads; ++t) pool.emplace_back(worker);
    worker();
}

}  // namespace lidarscout
