// Reads the process's resident set size from /proc.
#include "core/process_memory.hpp"

#include <unistd.h>

#include <fstream>

namespace lidarscout {

std::uint64_t resident_bytes() {
    std::ifstream in("/proc/self/statm");
    std::uint64_t size = 0, resident = 0;
    if (!(in >> size >> resident)) return 0;
    return resident * static_cast<std::uint64_t>(::sysconf(_SC_PAGESIZE));
}

}  // namespace lidarscout
