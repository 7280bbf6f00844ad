// io::File: reads served from the cached first/last 4 KiB equal plain reads everywhere in a
// file (across the cache edges too), and malformed offsets never wrap into the cache.
#include <gtest/gtest.h>

#include <fstream>
#include <iterator>

#include "core/error.hpp"
#include "io/file.hpp"
#include "test_data.hpp"

namespace lidarscout::io {
namespace {

std::vector<std::uint8_t> whole_file(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

TEST(File, ReadsEqualTheFileAcrossCachedEdges) {
    const auto path = (test::surveys_dir() / "ky-woodford-county").string();
    for (const auto& entry : std::filesystem::directory_iterator(path)) {
        const auto bytes = whole_file(entry.path().string());
        const auto f = File::open(entry.path().string());
        ASSERT_EQ(f.size(), bytes.size());
        const std::uint64_t n = bytes.size();
        const std::uint64_t edges[] = {0, 1, File::kCachedEdge - 7, File::kCachedEdge, n / 2, n - File::kCachedEdge - 3,
                                       n - File::kCachedEdge, n - 9};
        for (const auto at : edges) {
            for (const std::size_t len : {1u, 8u, 100u}) {
                std::vector<std::uint8_t> got(len);
                const std::size_t read = f.read_at(at, got);
                const std::size_t expected = static_cast<std::size_t>(std::min<std::uint64_t>(len, n - at));
                ASSERT_EQ(read, expected) << at;
                EXPECT_TRUE(std::equal(got.begin(), got.begin() + read, bytes.begin() + at)) << at << " " << len;
            }
        }
    }
}

TEST(File, HugeOffsetsDoNotWrapIntoTheCache) {
    const auto f = File::open((test::surveys_dir() / "ky-red-river-gorge" / "N105E348.laz").string());
    std::vector<std::uint8_t> out(512);
    EXPECT_EQ(f.read_at(~std::uint64_t{0} - 100, out), 0u);
    EXPECT_THROW(f.read_exact(~std::uint64_t{0} - 100, out), Error);
    EXPECT_THROW(f.read_vector(f.size() - 10, 20), Error);
}

// held: a view of the bytes the file holds in memory (its edges, an in-memory file's head), equal to a read; empty
// where they are not all held, and for offsets that would wrap.
TEST(File, HeldBytesAreTheFilesWhereItHoldsThem) {
    const auto path = (test::surveys_dir() / "ky-red-river-gorge" / "N105E348.laz").string();
    const auto bytes = whole_file(path);
    const auto f = File::open(path);
    const std::uint64_t n = f.size();
    const auto head = f.held(10, 100);
    ASSERT_EQ(head.size(), 100u);
    EXPECT_TRUE(std::equal(head.begin(), head.end(), bytes.begin() + 10));
    const auto tail = f.held(n - 50, 50);
    ASSERT_EQ(tail.size(), 50u);
    EXPECT_TRUE(std::equal(tail.begin(), tail.end(), bytes.end() - 50));
    EXPECT_TRUE(f.held(n / 2, 8).empty()) << "the middle is on disk";
    EXPECT_TRUE(f.held(File::kCachedEdge - 4, 8).empty()) << "past the head's edge";
    EXPECT_TRUE(f.held(~std::uint64_t{0} - 100, 200).empty());

    const auto memory = File::in_memory("memory.laz", 1000, std::vector<std::uint8_t>(600, 7), {1, 2, 3});
    EXPECT_EQ(memory.held(0, 600).size(), 600u);
    EXPECT_TRUE(memory.held(500, 200).empty()) << "past the head, before the tail";
    const auto last = memory.held(997, 3);
    ASSERT_EQ(last.size(), 3u);
    EXPECT_EQ(last[2], 3);
}

}  // namespace
}  // namespace lidarscout::io
