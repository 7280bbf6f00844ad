// lower_thread_priority: setpriority on the calling thread's id.
#include "core/thread_priority.hpp"

#include <sys/resource.h>
#include <unistd.h>

#include <cerrno>

namespace lidarscout {

void lower_thread_priority(int steps) {
    if (steps <= 0) return;
    errno = 0;
    const int nice = ::getpriority(PRIO_PROCESS, 0);
    if (errno == 0) ::setpriority(PRIO_PROCESS, static_cast<id_t>(::gettid()), nice + steps);
}

}  // namespace lidarscout
