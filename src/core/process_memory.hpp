// The process's resident memory, for memory-budget checks in tests, benchmarks and the
// viewer's stats panel; what the C heap holds of it; and the allocator settings under which
// memory the viewer frees goes back to the system (so that a budget on what it holds bounds
// the resident size).
#pragma once

#include <cstdint>

namespace lidarscout {

// Bytes resident now (/proc/self/statm); 0 where it cannot be read.
std::uint64_t resident_bytes();
// The most bytes ever resident (the high-water mark, VmHWM of /proc/self/status); 0 where unknown.
std::uint64_t peak_resident_bytes();

// The memory this process may use: the least of the machine's RAM, the address-space and data
// limits (ulimit -v, -d) and the cgroup's memory.max; 1 GiB when none can be read.
std::uint64_t usable_memory_bytes();

// The C heap (glibc's mallinfo2, every arena): bytes handed out and not freed, bytes freed but
// kept by the allocator in its arenas, bytes in blocks mapped on their own (part of in_use).
struct HeapUse {
    std::uint64_t in_use = 0, free_kept = 0, mapped = 0;
};
HeapUse heap_use();

// Makes freed memory go back to the system: blocks of `mmap_threshold` bytes and more are mapped
// on their own (and unmapped when freed: glibc's threshold otherwise grows with every large block
// freed, after which such blocks come from the arenas and stay resident), and free memory at the
// top of an arena over `trim_threshold` is returned. Process-wide; idempotent.
void return_freed_memory(std::uint64_t mmap_threshold = 4u << 20, std::uint64_t trim_threshold = 4u << 20);

// Returns the free memory the arenas hold (malloc_trim); cheap enough after large releases.
void trim_heap();

}  // namespace lidarscout
