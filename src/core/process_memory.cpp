// Reads the process's resident set size from /proc, its memory limits, and the C heap's use from
// glibc; sets the allocator's thresholds.
#include "core/process_memory.hpp"

#include <malloc.h>
#include <sys/resource.h>
#include <unistd.h>

#include <algorithm>
#include <cstdlib>
#include <fstream>
#include <string>

namespace lidarscout {

std::uint64_t resident_bytes() {
    std::ifstream in("/proc/self/statm");
    std::uint64_t size = 0, resident = 0;
    if (!(in >> size >> resident)) return 0;
    return resident * static_cast<std::uint64_t>(::sysconf(_SC_PAGESIZE));
}

std::uint64_t peak_resident_bytes() {
    std::ifstream in("/proc/self/status");
    std::string line;
    while (std::getline(in, line)) {
        if (line.rfind("VmHWM:", 0) == 0) return std::strtoull(line.c_str() + 6, nullptr, 10) * 1024;  // kB
    }
    return 0;
}

std::uint64_t usable_memory_bytes() {
    std::uint64_t least = ~0ull;
    const long pages = ::sysconf(_SC_PHYS_PAGES), page = ::sysconf(_SC_PAGESIZE);
    if (pages > 0 && page > 0) least = static_cast<std::uint64_t>(pages) * page;
    for (const int resource : {RLIMIT_AS, RLIMIT_DATA}) {
        rlimit limit{};
        if (::getrlimit(resource, &limit) == 0 && limit.rlim_cur != RLIM_INFINITY) {
            least = std::min<std::uint64_t>(least, limit.rlim_cur);
        }
    }
    std::ifstream cgroup("/sys/fs/cgroup/memory.max");
    std::uint64_t cgroup_max = 0;
    if (cgroup >> cgroup_max && cgroup_max > 0) least = std::min(least, cgroup_max);  // "max" reads as no number
    return least == ~0ull ? (1ull << 30) : least;
}

HeapUse heap_use() {
    const struct mallinfo2 m = ::mallinfo2();
    return {m.uordblks + m.hblkhd, m.fordblks, m.hblkhd};
}

void return_freed_memory(std::uint64_t mmap_threshold, std::uint64_t trim_threshold) {
    ::mallopt(M_MMAP_THRESHOLD, static_cast<int>(mmap_threshold));
    ::mallopt(M_TRIM_THRESHOLD, static_cast<int>(trim_threshold));
}

void trim_heap() { ::malloc_trim(0); }

}  // namespace lidarscout
