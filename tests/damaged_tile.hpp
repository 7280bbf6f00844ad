// A copy of a real LAZ tile with one chunk damaged, for the tests that a corrupt chunk costs
// that chunk only: the Woodford County tile (21 chunks of 50,000 points) with 4 KiB in the
// middle of the file overwritten by a fixed pattern, which lands in chunk 9 (points
// 450,000..500,000) and makes its arithmetic decoder fail.
#pragma once

#include <cstdint>
#include <filesystem>
#include <fstream>
#include <string>

#include "test_data.hpp"

namespace lidarscout::test {

inline constexpr const char* kDamagedChunkText = "chunk 9 (points 450000..500000)";
inline constexpr std::uint64_t kDamagedChunkPoints = 50'000;

// Writes the damaged copy into `dir` and returns its path.
inline std::filesystem::path damaged_tile(const std::filesystem::path& dir) {
    const auto source = surveys_dir() / "ky-woodford-county" / "5205000_3900000.laz";
    const auto copy = dir / "damaged.laz";
    std::filesystem::copy_file(source, copy, std::filesystem::copy_options::overwrite_existing);
    std::filesystem::permissions(copy, std::filesystem::perms::owner_write, std::filesystem::perm_options::add);
    std::fstream f(copy, std::ios::in | std::ios::out | std::ios::binary);
    f.seekp(static_cast<std::streamoff>(std::filesystem::file_size(copy) / 2));
    for (int i = 0; i < 4096; ++i) f.put(static_cast<char>((i * 131 + 7) & 255));
    return copy;
}

}  // namespace lidarscout::test
