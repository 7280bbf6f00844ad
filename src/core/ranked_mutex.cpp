// RankedMutex: the thread's held ranked mutexes, the order check, and the plain mutex beneath.
#include "core/ranked_mutex.hpp"

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <vector>

namespace lidarscout {
namespace {

thread_local std::vector<const RankedMutex*> held;  // in the order taken

}  // namespace

void RankedMutex::check_order() const {
    for (const RankedMutex* h : held) {
        if (h->rank() < rank_) continue;
        std::fprintf(stderr, "lidarscout: lock order broken: taking \"%s\" (rank %d) while holding \"%s\" (rank %d)\n",
                     name_, rank_, h->name(), h->rank());
        std::abort();
    }
}

void RankedMutex::lock() {
    check_order();
    mutex_.lock();
    held.push_back(this);
}

bool RankedMutex::try_lock() {
    check_order();
    if (!mutex_.try_lock()) return false;
    held.push_back(this);
    return true;
}

void RankedMutex::unlock() {
    const auto it = std::find(held.rbegin(), held.rend(), this);
    if (it != held.rend()) held.erase(std::next(it).base());
    mutex_.unlock();
}

}  // namespace lidarscout
