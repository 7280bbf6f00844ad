// Every file the reference LASzip decodes (144: LAS and all LAZ variants) gives the same
// SHA-256 over its point records through for_each_record_batch, whatever the batch size.
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

// The reference hashes of COPC files with several chunks list the points in octree node
// order, not file order; tests/laz/point14/layered_decode_test.cpp checks those 7 files.
bool copc_with_several_chunks(const Expected& e) {
    return e.name.find(".copc.laz") != std::string::npos && e.json.contains("chunks") && e.json.at("chunks").size() > 1;
}

std::vector<Expected> decodable() {
    std::vector<Expected> out;
    for (auto& e : test::all_expected()) {
        if (e.json.at("reference_result") == "decodes") out.push_back(std::move(e));
    }
    return out;
}

std::vector<Expected> file_order_hashed() {
    auto all = decodable();
    std::erase_if(all, copc_with_several_chunks);
    return all;
}

std::string checksum(const std::string& path, std::uint64_t batch_points, std::uint64_t& points) {
    auto file = io::File::open(path);
    auto tile = dataset::read_tile(file);
    static ThreadPool pool(2);
    Sha256 sha;
    points = 0;
    dataset::for_each_record_batch(file, tile, pool, [&](std::uint64_t first, std::span<const std::uint8_t> records) {
        EXPECT_EQ(first, points);
        points += records.size() / tile.header.record_length;
        sha.update(records);
    }, laz::fields::kAll, batch_points);
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
}

std::string test_name(const ::testing::TestParamInfo<Expected>& info) {
    std::string s = info.param.name;
    for (char& c : s) if (!std::isalnum(static_cast<unsigned char>(c))) c = '_';
    return s;
}

INSTANTIATE_TEST_SUITE_P(Formats, PointsSha256, ::testing::ValuesIn(file_order_hashed()), test_name);

TEST(PointsSha256Corpus, AllDecodableFiles) {
    EXPECT_EQ(decodable().size(), 144u);
    EXPECT_EQ(file_order_hashed().size(), 137u);
}

}  // namespace
}  // namespace lidarscout
