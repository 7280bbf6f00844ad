// The test binary's global operator new and delete (malloc and free underneath), counting the
// bytes asked while an AllocationCounter is alive, and the most held at once.
#include "allocation_counter.hpp"

#include <malloc.h>

#include <atomic>
#include <cstdint>
#include <cstdlib>
#include <new>

namespace {

std::atomic<bool> g_counting{false};
std::atomic<std::size_t> g_bytes{0};
std::atomic<std::int64_t> g_held{0}, g_peak{0};  // bytes held (allocated less freed) since the start, the most

void hold(void* p) {
    const auto size = static_cast<std::int64_t>(malloc_usable_size(p));
    const std::int64_t held = g_held.fetch_add(size, std::memory_order_relaxed) + size;
    std::int64_t peak = g_peak.load(std::memory_order_relaxed);
    while (held > peak && !g_peak.compare_exchange_weak(peak, held, std::memory_order_relaxed)) {
    }
}

void* allocate(std::size_t size, std::size_t alignment) {
    const bool counting = g_counting.load(std::memory_order_relaxed);
    if (counting) g_bytes.fetch_add(size, std::memory_order_relaxed);
    if (size == 0) size = 1;
    void* p = alignment <= alignof(std::max_align_t)
                  ? std::malloc(size)
                  : std::aligned_alloc(alignment, (size + alignment - 1) / alignment * alignment);
    if (counting && p) hold(p);
    return p;
}

void release(void* p) {
    if (p && g_counting.load(std::memory_order_relaxed)) {
        g_held.fetch_sub(static_cast<std::int64_t>(malloc_usable_size(p)), std::memory_order_relaxed);
    }
    std::free(p);
}

void* allocate_or_throw(std::size_t size, std::size_t alignment) {
    void* p = allocate(size, alignment);
    if (!p) throw std::bad_alloc();
    return p;
}

}  // namespace

namespace lidarscout::test {

AllocationCounter::AllocationCounter() {
    g_bytes.store(0);
    g_held.store(0);
    g_peak.store(0);
    g_counting.store(true);
}

AllocationCounter::~AllocationCounter() { g_counting.store(false); }

std::size_t AllocationCounter::bytes() const { return g_bytes.load(); }

std::size_t AllocationCounter::peak_bytes() const { return static_cast<std::size_t>(g_peak.load()); }

}  // namespace lidarscout::test

void* operator new(std::size_t size) { return allocate_or_throw(size, 0); }
void* operator new[](std::size_t size) { return allocate_or_throw(size, 0); }
void* operator new(std::size_t size, std::align_val_t a) { return allocate_or_throw(size, std::size_t(a)); }
void* operator new[](std::size_t size, std::align_val_t a) { return allocate_or_throw(size, std::size_t(a)); }
void* operator new(std::size_t size, const std::nothrow_t&) noexcept { return allocate(size, 0); }
void* operator new[](std::size_t size, const std::nothrow_t&) noexcept { return allocate(size, 0); }
void operator delete(void* p) noexcept { release(p); }
void operator delete[](void* p) noexcept { release(p); }
void operator delete(void* p, std::size_t) noexcept { release(p); }
void operator delete[](void* p, std::size_t) noexcept { release(p); }
void operator delete(void* p, std::align_val_t) noexcept { release(p); }
void operator delete[](void* p, std::align_val_t) noexcept { release(p); }
void operator delete(void* p, std::size_t, std::align_val_t) noexcept { release(p); }
void operator delete[](void* p, std::size_t, std::align_val_t) noexcept { release(p); }
