// Chunk points of every chunked LAZ file equal the first point of each chunk as the reference
// LASzip decodes it; LAS files give every 50,000th record.
#include <gtest/gtest.h>

#include <bit>
#include <cstring>

#include "dataset/chunk_points.hpp"
#include "dataset/tile.hpp"
#include "io/file.hpp"
#include "test_data.hpp"

namespace lidarscout {
namespace {

using test::Expected;

std::vector<Expected> with_chunk_points() {
    std::vector<Expected> out;
    for (auto& e : test::all_expected()) {
        const auto& j = *e.json;
        if (j.contains("chunks") && !j.at("chunks").empty() && j.at("reference_result") == "decodes") {
            out.push_back(std::move(e));
        }
    }
    return out;
}

class ChunkPointsMatchReference : public ::testing::TestWithParam<Expected> {};

TEST_P(ChunkPointsMatchReference, RawFieldsEqual) {
    const auto& e = GetParam();
    auto file = io::File::open(e.file.string());
    auto tile = dataset::read_tile(file);
    auto points = dataset::read_chunk_points(file, tile);
    const auto& want = e.json->at("chunk_points");
    ASSERT_EQ(points.size(), want.size());
    const auto& fmt = las::point_format_info(tile.header.point_format);
    for (std::size_t i = 0; i < points.size(); ++i) {
        const auto& p = points[i].point;
        const auto& w = want[i];
        SCOPED_TRACE("chunk point " + std::to_string(i));
        EXPECT_EQ(points[i].index, w.at("index").get<std::uint64_t>());
        EXPECT_EQ(points[i].index, e.json->at("chunks")[i].at("first_point").get<std::uint64_t>());
        EXPECT_EQ(p.X, w.at("X").get<std::int32_t>());
        EXPECT_EQ(p.Y, w.at("Y").get<std::int32_t>());
        EXPECT_EQ(p.Z, w.at("Z").get<std::int32_t>());
        EXPECT_EQ(p.intensity, w.at("intensity").get<int>());
        EXPECT_EQ(p.return_number, w.at("ret").get<int>());
        EXPECT_EQ(p.number_of_returns, w.at("nret").get<int>());
        EXPECT_EQ(p.classification, w.at("class").get<int>());
        EXPECT_EQ(p.scan_angle_raw, w.at(fmt.extended ? "scan_angle" : "scan_angle_rank").get<int>());
        EXPECT_EQ(p.user_data, w.at("user_data").get<int>());
        EXPECT_EQ(p.point_source_id, w.at("psid").get<int>());
        if (fmt.gps_offset >= 0) {
            const auto bits = std::stoull(w.at("gps_time_bits").get<std::string>(), nullptr, 16);
            EXPECT_EQ(std::bit_cast<std::uint64_t>(p.gps_time), bits);
        }
        if (fmt.rgb_offset >= 0) {
            for (int c = 0; c < 3; ++c) EXPECT_EQ(p.rgb[c], w.at("rgb")[c].get<int>());
        }
    }
}

std::string test_name(const ::testing::TestParamInfo<Expected>& info) {
    std::string s = info.param.name;
    for (char& c : s) if (!std::isalnum(static_cast<unsigned char>(c))) c = '_';
    return s;
}

INSTANTIATE_TEST_SUITE_P(Formats, ChunkPointsMatchReference, ::testing::ValuesIn(with_chunk_points()), test_name);

TEST(ChunkPointsReference, SeventyChunkedFiles) { EXPECT_EQ(with_chunk_points().size(), 70u); }

TEST(ChunkPointsLas, EveryFiftyThousandthRecord) {
    const auto path = (test::formats_dir() / "PDAL__PDAL/test__data__las__autzen_trim.las").string();
    auto file = io::File::open(path);
    auto tile = dataset::read_tile(file);
    auto points = dataset::read_chunk_points(file, tile);
    ASSERT_EQ(points.size(), 3u);  // 110,000 points: records 0, 50,000, 100,000
    for (std::size_t i = 0; i < points.size(); ++i) {
        EXPECT_EQ(points[i].index, i * 50'000);
        std::vector<std::uint8_t> rec(tile.header.record_length);
        file.read_exact(tile.header.offset_to_point_data + points[i].index * rec.size(), rec);
        std::int32_t X;
        std::memcpy(&X, rec.data(), 4);
        EXPECT_EQ(points[i].point.X, X);
        EXPECT_DOUBLE_EQ(points[i].point.x, X * tile.header.scale[0] + tile.header.offset[0]);
    }
    EXPECT_EQ(dataset::read_chunk_points(file, tile, 1000).size(), 110u);
}

}  // namespace
}  // namespace lidarscout
