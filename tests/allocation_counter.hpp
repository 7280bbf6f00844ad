// Counting what the code under test allocates, so tests of hostile inputs assert on bytes (a
// count) rather than on seconds: while an AllocationCounter lives, every operator new of the
// process (any thread) adds its size to it. The test binary replaces the global operator new
// (allocation_counter.cpp); outside a counter it costs one relaxed atomic load.
#pragma once

#include <cstddef>

namespace lidarscout::test {

class AllocationCounter {
public:
    AllocationCounter();
    ~AllocationCounter();
    AllocationCounter(const AllocationCounter&) = delete;
    AllocationCounter& operator=(const AllocationCounter&) = delete;

    // Bytes asked of operator new since this counter started (frees are not subtracted).
    std::size_t bytes() const;
    // The most bytes held at once since this counter started: blocks allocated less blocks freed
    // (as malloc sized them; a block freed that was allocated before the counter counts too).
    std::size_t peak_bytes() const;
};

}  // namespace lidarscout::test
