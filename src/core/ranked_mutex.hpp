// A mutex with a rank, so that a lock order written beside the locks is also checked: a thread that
// takes a ranked mutex while it holds one of the same or a higher rank has broken the order (two
// threads doing it the other way round deadlock), and the process stops at once with both names on
// stderr, in every build (the check is a thread-local list of the ranked mutexes held: a few
// nanoseconds per lock). Lockable, so it works with std::lock_guard, std::unique_lock and
// std::condition_variable_any.
#pragma once

#include <mutex>

namespace lidarscout {

class RankedMutex {
public:
    // Lower ranks are taken first; `name` appears in the message (a string literal).
    RankedMutex(int rank, const char* name) : rank_(rank), name_(name) {}
    RankedMutex(const RankedMutex&) = delete;
    RankedMutex& operator=(const RankedMutex&) = delete;

    void lock();
    bool try_lock();
    void unlock();

    int rank() const { return rank_; }
    const char* name() const { return name_; }

private:
    void check_order() const;  // aborts when the calling thread holds a mutex of this rank or higher

    std::mutex mutex_;
    const int rank_;
    const char* const name_;
};

}  // namespace lidarscout
