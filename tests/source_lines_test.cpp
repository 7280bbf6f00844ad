// A rule of the code base checked on the tree itself: no line of C++ or CUDA source under
// src/, tests/, bench/ or fuzz/ is longer than 120 columns (characters, UTF-8 counted once).
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <set>
#include <string>

namespace {

namespace fs = std::filesystem;

constexpr std::size_t kMaxColumns = 120;

std::size_t columns(const std::string& line) {
    std::size_t n = 0;
    for (const unsigned char c : line) n += (c & 0xC0) != 0x80;  // continuation bytes do not count
    return n;
}

TEST(SourceLines, AtMost120Columns) {
    const std::set<std::string> extensions = {".cpp", ".hpp", ".h", ".cu", ".cuh"};
    std::size_t files = 0;
    std::string long_lines;
    for (const char* top : {"src", "tests", "bench", "fuzz"}) {
        for (const auto& e : fs::recursive_directory_iterator(fs::path(LIDARSCOUT_SOURCE_DIR) / top)) {
            if (!e.is_regular_file() || !extensions.count(e.path().extension().string())) continue;
            ++files;
            std::ifstream in(e.path());
            std::string line;
            for (std::size_t n = 1; std::getline(in, line); ++n) {
                if (columns(line) > kMaxColumns) long_lines += e.path().string() + ":" + std::to_string(n) + "\n";
            }
        }
    }
    EXPECT_GT(files, 100u);  // the tree was found
    EXPECT_TRUE(long_lines.empty()) << "lines over " << kMaxColumns << " columns:\n" << long_lines;
}

}  // namespace
