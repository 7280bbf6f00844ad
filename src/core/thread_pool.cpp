// ThreadPool implementation: loops are queued; each worker that picks a loop pulls indices
// from its shared counter until they run out.
#include "core/thread_pool.hpp"

#include <algorithm>
#include <memory>
#include <string>
#include <system_error>

#include "core/error.hpp"

namespace lidarscout {

struct ThreadPool::Loop {
    std::size_t n;
    const std::function<void(std::size_t)>* fn;
    std::atomic<std::size_t> next{0};
    std::atomic<unsigned> active{0};  // workers currently inside this loop
    std::mutex error_mutex;
    std::exception_ptr error;

    void work() {
        for (std::size_t i; (i = next.fetch_add(1, std::memory_order_relaxed)) < n;) {
            try {
                (*fn)(i);
            } catch (...) {
                std::lock_guard lock(error_mutex);
                if (!error) error = std::current_exception();
                next.store(n, std::memory_order_relaxed);  // stop handing out work
            }
        }
    }
};

namespace {
std::atomic<unsigned> g_shared_threads{0};
constexpr unsigned kThreadsPerCore = 4, kMostThreads = 256;
}  // namespace

unsigned max_threads() noexcept {
    return std::min(kMostThreads, kThreadsPerCore * std::max(1u, std::thread::hardware_concurrency()));
}

unsigned capped_threads(unsigned requested) noexcept { return std::min(requested, max_threads()); }

ThreadPool::ThreadPool(unsigned threads) {
    threads = std::clamp(threads, 1u, max_threads());
    workers_.reserve(threads - 1);
    try {
        for (unsigned t = 1; t < threads; ++t) workers_.emplace_back([this] { worker_main(); });
    } catch (const std::system_error& e) {  // the system refused a thread: join those started
        stop_workers();
        throw Error::in_stage("threads", "cannot start thread " + std::to_string(workers_.size() + 1) + " of " +
                                             std::to_string(threads) + ": " + e.what());
    }
}

ThreadPool::~ThreadPool() { stop_workers(); }

void ThreadPool::stop_workers() {
    {
        std::lock_guard lock(mutex_);
        stopping_ = true;
    }
    wake_.notify_all();
    for (auto& w : workers_) w.join();
}

void ThreadPool::worker_main() {
    for (;;) {
        Loop* loop = nullptr;
        {
            std::unique_lock lock(mutex_);
            wake_.wait(lock, [&] { return stopping_ || !queue_.empty(); });
            if (stopping_) return;
            loop = queue_.front();
            if (loop->next.load(std::memory_order_relaxed) >= loop->n) {
                queue_.pop_front();  // exhausted: let the next loop be picked
                continue;
            }
            loop->active.fetch_add(1);
        }
        loop->work();
        {
            std::lock_guard lock(mutex_);
            loop->active.fetch_sub(1);
        }
        wake_.notify_all();
    }
}

void ThreadPool::run_loop(std::size_t n, const std::function<void(std::size_t)>& fn) {
    if (n == 0) return;
    Loop loop;
    loop.n = n;
    loop.fn = &fn;
    if (!workers_.empty() && n > 1) {
        {
            std::lock_guard lock(mutex_);
            queue_.push_back(&loop);
        }
        wake_.notify_all();
    }
    loop.work();
    {
        // Wait until no worker is inside the loop and it is out of the queue.
        std::unique_lock lock(mutex_);
        auto it = std::find(queue_.begin(), queue_.end(), &loop);
        if (it != queue_.end()) queue_.erase(it);
        wake_.wait(lock, [&] { return loop.active.load() == 0; });
    }
    if (loop.error) std::rethrow_exception(loop.error);
}

unsigned ThreadPool::shared_size() {
    return g_shared_threads.load() ? g_shared_threads.load() : std::max(1u, std::thread::hardware_concurrency());
}

ThreadPool& ThreadPool::shared() {
    static ThreadPool pool(shared_size());
    return pool;
}

void ThreadPool::set_shared_threads(unsigned threads) { g_shared_threads.store(threads); }

}  // namespace lidarscout
