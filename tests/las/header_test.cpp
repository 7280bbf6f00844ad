// Header parsing: every file the reference reads has the same header fields as LASzip reports;
// hand-made broken headers are rejected with precise messages.
#include <gtest/gtest.h>

#include <unistd.h>

#include <cstring>
#include <fstream>

#include "core/error.hpp"
#include "io/file.hpp"
#include "las/header.hpp"
#include "test_data.hpp"

namespace lidarscout {
namespace {

using test::Expected;

class HeaderMatchesReference : public ::testing::TestWithParam<Expected> {};

TEST_P(HeaderMatchesReference, SameFieldsAsLaszip) {
    const auto& e = GetParam();
    const auto& x = e.json->at("header");
    auto file = io::File::open(e.file.string());
    auto h = las::read_header(file);
    EXPECT_EQ(h.version_string(), x.at("version").get<std::string>());
    EXPECT_EQ(h.header_size, x.at("header_size").get<int>());
    EXPECT_EQ(h.offset_to_point_data, x.at("offset_to_point_data").get<std::uint32_t>());
    EXPECT_EQ(h.number_of_vlrs, x.at("number_of_vlrs").get<std::uint32_t>());
    EXPECT_EQ(h.point_format, x.at("point_format").get<int>());
    EXPECT_EQ(h.compressed, x.at("compressed").get<bool>());
    EXPECT_EQ(h.record_length, x.at("record_length").get<int>());
    EXPECT_EQ(h.point_count, x.at("point_count").get<std::uint64_t>());
    for (int i = 0; i < 3; ++i) {
        EXPECT_EQ(h.scale[i], x.at("scale")[i].get<double>());
        EXPECT_EQ(h.offset[i], x.at("offset")[i].get<double>());
        EXPECT_EQ(h.min[i], x.at("bounds").at("min")[i].get<double>());
        EXPECT_EQ(h.max[i], x.at("bounds").at("max")[i].get<double>());
    }
}

std::vector<Expected> decodable() {
    std::vector<Expected> out;
    for (auto& e : test::all_expected()) {
        if (e.json->at("reference_result") == "decodes") out.push_back(std::move(e));
    }
    return out;
}

std::string test_name(const ::testing::TestParamInfo<Expected>& info) {
    std::string s = info.param.name;
    for (char& c : s) if (!std::isalnum(static_cast<unsigned char>(c))) c = '_';
    return s;
}

INSTANTIATE_TEST_SUITE_P(Formats, HeaderMatchesReference, ::testing::ValuesIn(decodable()), test_name);

TEST(HeaderFormats, ReferenceCoversAllDecodableFiles) { EXPECT_EQ(decodable().size(), 144u); }

// A scratch file holding the first bytes of a real header, then edited.
class BrokenHeader : public ::testing::Test {
protected:
    std::string path =
        (std::filesystem::temp_directory_path() / ("lidarscout_header_" + std::to_string(::getpid()) + ".las"))
            .string();
    std::vector<char> bytes;

    void SetUp() override {
        std::ifstream in(test::formats_dir() / "PDAL__PDAL/test__data__las__autzen_trim.las", std::ios::binary);
        bytes.assign(std::istreambuf_iterator<char>(in), {});
        ASSERT_GT(bytes.size(), 2038u);
    }
    void TearDown() override { std::filesystem::remove(path); }

    template <typename T>
    void put(std::size_t at, T v) { std::memcpy(bytes.data() + at, &v, sizeof v); }

    std::string error() {
        std::ofstream(path, std::ios::binary).write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
        try {
            las::read_header(io::File::open(path));
        } catch (const Error& e) {
            EXPECT_EQ(e.file(), path);
            return e.cause();
        }
        return "no error";
    }
};

TEST_F(BrokenHeader, ValidCopyReads) { EXPECT_EQ(error(), "no error"); }

TEST_F(BrokenHeader, Signature) {
    bytes[0] = 'X';
    EXPECT_EQ(error(), "not a LAS/LAZ file: no 'LASF' signature");
}

TEST_F(BrokenHeader, Version) {
    bytes[24] = 2;
    EXPECT_EQ(error(), "unsupported LAS version 2.2");
}

TEST_F(BrokenHeader, HeaderSizeTooSmall) {
    put<std::uint16_t>(94, 200);
    EXPECT_EQ(error(), "header size 200 is smaller than the 227 bytes LAS 1.2 requires");
}

TEST_F(BrokenHeader, PointDataBeyondFile) {
    put<std::uint32_t>(96, 1u << 30);
    EXPECT_NE(error().find("offset to point data 1073741824 is beyond the end of the file"), std::string::npos);
}

TEST_F(BrokenHeader, RecordTooShortForFormat) {
    put<std::uint16_t>(105, 30);
    EXPECT_EQ(error(), "point record length 30 is too short for point format 3 (needs at least 34)");
}

TEST_F(BrokenHeader, UnknownFormat) {
    bytes[104] = 11;
    EXPECT_EQ(error(), "unknown point data record format 11");
}

TEST_F(BrokenHeader, PointCountDoesNotFit) {
    put<std::uint32_t>(107, 110001);
    EXPECT_NE(error().find("header announces 110001 points of 34 bytes but the file holds only 110000"),
              std::string::npos);
}

TEST_F(BrokenHeader, ZeroScale) {
    put<double>(131, 0.0);
    EXPECT_NE(error().find("scale factor"), std::string::npos);
}

TEST_F(BrokenHeader, TruncatedHeader) {
    bytes.resize(100);
    EXPECT_NE(error().find("truncated header"), std::string::npos);
}

}  // namespace
}  // namespace lidarscout
