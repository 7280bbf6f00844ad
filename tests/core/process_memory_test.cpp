// The process's peak resident memory (VmHWM), which `dem --json` reports: never below what is
// resident, and so at least a large allocation that is touched (an earlier test may have set it higher).
#include <gtest/gtest.h>

#include <cstring>
#include <memory>

#include "core/process_memory.hpp"

namespace lidarscout {
namespace {

TEST(ProcessMemory, PeakResidentBytesIsTheHighWaterMark) {
    const std::uint64_t resident = resident_bytes();  // (first: reading the peak may itself touch a new page)
    ASSERT_GT(resident, 0u);
    EXPECT_GE(peak_resident_bytes(), resident);
    constexpr std::size_t kBytes = std::size_t(256) << 20;
    auto block = std::make_unique<char[]>(kBytes);
    std::memset(block.get(), 1, kBytes);  // touched: resident
    const std::uint64_t now = resident_bytes();
    EXPECT_GE(now, kBytes);
    EXPECT_GE(peak_resident_bytes(), now);
    volatile char sink = block[kBytes - 1];
    (void)sink;
}

}  // namespace
}  // namespace lidarscout
