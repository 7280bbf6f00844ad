// Rules of the code base checked on the tree itself: no line of C++ or CUDA source under
// src/, tests/, bench/ or fuzz/ is longer than 120 columns (characters, UTF-8 counted once); no
// test asserts on wall-clock time (speed is measured by bench/, tests assert on counts).
#include "test_paths.hpp"
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <regex>
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

// An assertion that reads a clock, or compares a duration or a `seconds` / `elapsed` figure with
// a constant, asserts on wall-clock time: slow or loaded machines make it fail, fast ones hide
// what it meant. (Timeouts that end a wait are not assertions and stay allowed.)
bool asserts_on_time(const std::string& line) {
    static const std::regex assertion(R"(\b(EXPECT|ASSERT)_[A-Z_]+\()");
    static const std::regex timed(
        R"(clock::now|chrono::(seconds|milliseconds|microseconds)\(|\b(seconds|elapsed)\s*,\s*[0-9.]+\s*\))");
    return std::regex_search(line, assertion) && std::regex_search(line, timed);
}

TEST(SourceRules, NoTestAssertsOnWallClockTime) {
    // the rule sees what it forbids (the examples are assembled, so this file holds no such line)
    const std::string lt = std::string("EXPECT") + "_LT(";
    EXPECT_TRUE(asserts_on_time(lt + "seconds, " + "0.5);"));
    EXPECT_TRUE(asserts_on_time(lt + "std::chrono::steady_clock::" + "now() - t0, std::chrono::" + "seconds(30));"));
    EXPECT_FALSE(asserts_on_time(std::string("EXPECT") + "_EQ(server.requests(), 2);"));
    std::string timed;
    for (const auto& e : fs::recursive_directory_iterator(fs::path(LIDARSCOUT_SOURCE_DIR) / "tests")) {
        if (!e.is_regular_file()) continue;
        std::ifstream in(e.path());
        std::string line;
        for (std::size_t n = 1; std::getline(in, line); ++n) {
            if (asserts_on_time(line)) timed += e.path().string() + ":" + std::to_string(n) + ": " + line + "\n";
        }
    }
    EXPECT_TRUE(timed.empty()) << "assertions on wall-clock time:\n" << timed;
}

}  // namespace
