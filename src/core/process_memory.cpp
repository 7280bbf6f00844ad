// Reads the process's resident set size from /proc and the C heap's use from glibc; sets the
// allocator's thresholds.
#include "core/process_memory.hpp"

#include <malloc.h>
#include <unistd.h>

#include <fstream>

namespace lidarscout {

std::uint64_t resident_bytes() {
    std::ifstream in("/proc/self/statm");
    std::uint64_t size = 0, resident = 0;
    if (!(in >> size >> resident)) return 0;
    return resident * static_cast<std::uint64_t>(::sysconf(_SC_PAGESIZE));
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
