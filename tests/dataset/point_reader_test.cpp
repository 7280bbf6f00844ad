// Every file the reference LASzip decodes (144: LAS and all LAZ variants) gives the same
// SHA-256 over its point records through for_each_record_batch, whatever the batch size and
// with or without read-ahead.
#include <gtest/gtest.h>

#include "core/sha256.hpp"
#include "core/thread_pool.hpp"
#include "dataset/point_reader.hpp"
#include "dataset/tile.hpp"
#include "io/file.hpp"
#include "test_data.hpp"

namespace lidarscout {
namespace {

using test::Expected;

std::vector<Expected> decodable() {
    std::vector<Expected> out;
    for (auto& e : test::all_expected()) {
        if (e.json.at("reference_result") == "decodes") out.push_back(std::move(e));
    }
    return out;
}

std::string checksum(const std::string& path, std::uint64_t batch_points, std::uint64_t& points,
                     bool read_ahead = false) {
    auto file = io::File::open(path);
    auto tile = dataset::read_tile(file);
    static ThreadPool pool(2);
    Sha256 sha;
    points = 0;
    dataset::for_each_record_batch(file, tile, pool, [&](std::uint64_t first, std::span<const std::uint8_t> records) {
        EXPECT_EQ(first, points);
        points += records.size() / tile.header.record_length;
        sha.update(records);
    }, laz::fields::kAll, batch_points, read_ahead);
    EXPECT_EQ(points, tile.header.point_count);
    return sha.hex_digest();
}

class PointsSha256 : public ::testing::TestWithParam<Expected> {};

TEST_P(PointsSha256, MatchesReference) {
    const auto& e = GetParam();
    std::uint64_t points = 0;
    EXPECT_EQ(checksum(e.file.string(), 1u << 20, points), e.json.at("points_sha256").get<std::string>());
    // Small batches: many batch boundaries (one chunk each for LAZ, 997 records for LAS).
    EXPECT_EQ(checksum(e.file.string(), 997, points), e.json.at("points_sha256").get<std::string>());
    // The same with the next batch read while this one is used.
    EXPECT_EQ(checksum(e.file.string(), 997, points, true), e.json.at("points_sha256").get<std::string>());
}

std::string test_name(const ::testing::TestParamInfo<Expected>& info) {
    std::string s = info.param.name;
    for (char& c : s) if (!std::isalnum(static_cast<unsigned char>(c))) c = '_';
    return s;
}

INSTANTIATE_TEST_SUITE_P(Formats, PointsSha256, ::testing::ValuesIn(decodable()), test_name);

TEST(PointsSha256Corpus, AllDecodableFiles) {
    // Every hash is in file order (COPC included: the reference reads it as LASzip's library does).
    EXPECT_EQ(decodable().size(), 144u);
}

}  // namespace
}  // namespace lidarscout
