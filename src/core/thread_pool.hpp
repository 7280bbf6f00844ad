// The library's thread pool: a fixed set of workers that run index loops (chunk decoding,
// header reading) with dynamic scheduling. The calling thread helps, so nested or
// single-thread use cannot dead-lock. The first exception thrown by an iteration stops the
// loop and is rethrown to the caller. No pool or thread option starts more than max_threads()
// threads (4 per core, at most 256): 100,000 threads stall the whole machine.
#pragma once

#include <algorithm>
#include <atomic>
#include <condition_variable>
#include <cstddef>
#include <deque>
#include <exception>
#include <functional>
#include <mutex>
#include <thread>
#include <vector>

namespace lidarscout {

// The most threads a pool or a thread option may start: 4 per hardware thread, at most 256.
unsigned max_threads() noexcept;
// `requested` lowered to max_threads() (0 stays 0: "the default").
unsigned capped_threads(unsigned requested) noexcept;

class ThreadPool {
public:
    // `threads` counts the calling thread: a pool of 1 runs everything on the caller. At most
    // max_threads() are started (the CLI warns about a larger option: cli/thread_options.hpp).
    explicit ThreadPool(unsigned threads);
    ~ThreadPool();
    ThreadPool(const ThreadPool&) = delete;
    ThreadPool& operator=(const ThreadPool&) = delete;

    unsigned size() const noexcept { return static_cast<unsigned>(workers_.size()) + 1; }

    // Runs fn(i) for every i in [0, n); returns when all are done.
    template <typename Fn>
    void for_each(std::size_t n, Fn&& fn) {
        std::function<void(std::size_t)> f = std::forward<Fn>(fn);
        run_loop(n, f);
    }

    // Runs fn(begin, end) for the blocks of `block` indices that cover [0, n) (the last one shorter): a loop whose
    // iterations are too small to be handed out one at a time.
    template <typename Fn>
    void for_each_block(std::size_t n, std::size_t block, Fn&& fn) {
        for_each((n + block - 1) / block, [&](std::size_t b) { fn(b * block, std::min(n, (b + 1) * block)); });
    }

    // The pool shared by the library (created on first use with set_shared_threads' size,
    // default: all hardware threads).
    static ThreadPool& shared();
    // Sets the size of the shared pool; call before its first use (e.g. from --threads).
    static void set_shared_threads(unsigned threads);
    // The shared pool's size (what --threads set, else every hardware thread), without starting it: for a pool of
    // its own that must keep the user's bound (e.g. one whose threads run at a lower priority).
    static unsigned shared_size();

private:
    struct Loop;
    void run_loop(std::size_t n, const std::function<void(std::size_t)>& fn);
    void worker_main();
    void stop_workers();  // tells the workers to stop and joins them

    std::vector<std::thread> workers_;
    std::mutex mutex_;
    std::condition_variable wake_;
    std::deque<Loop*> queue_;
    bool stopping_ = false;
};

}  // namespace lidarscout
