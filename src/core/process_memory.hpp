// The process's resident memory, for memory-budget checks in tests, benchmarks and the
// viewer's stats panel.
#pragma once

#include <cstdint>

namespace lidarscout {

// Bytes resident now (/proc/self/statm); 0 where it cannot be read.
std::uint64_t resident_bytes();

}  // namespace lidarscout
