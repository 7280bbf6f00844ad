// The LASzip VLR: every LAZ file the reference decodes gives the same compressor, chunk size
// and items as LASzip reports; LASzip's deliberately broken files and hand-made payloads
// with each kind of defect are rejected with a message naming the defect.
#include <gtest/gtest.h>

#include <cctype>
#include <map>
#include <string>
#include <vector>

#include "core/error.hpp"
#include "io/file.hpp"
#include "las/header.hpp"
#include "las/laszip_vlr.hpp"
#include "las/vlr.hpp"
#include "test_data.hpp"

namespace lidarscout::las {
namespace {

using lidarscout::test::Expected;

std::string readable(const ::testing::TestParamInfo<Expected>& info) {
    std::string s = info.param.name;
    for (char& c : s) if (!std::isalnum(static_cast<unsigned char>(c))) c = '_';
    return s;
}

// The LASzip VLR of a data file, parsed.
LaszipVlr laszip_of(const std::filesystem::path& path) {
    auto file = io::File::open(path.string());
    const auto header = read_header(file);
    const auto vlrs = read_vlrs(file, header);
    const Vlr* v = find_vlr(vlrs, "laszip encoded", 22204);
    if (!v) throw Error(path.string(), std::nullopt, "test: no laszip VLR");
    return parse_laszip_vlr(v->data, file.path(), v->data_offset);
}

bool is_broken_on_purpose(const Expected& e) { return e.name.find("LASzip__LASzip__data__broken_") == 0; }

std::vector<Expected> files_with_laz(bool broken) {
    std::vector<Expected> out;
    for (auto& e : lidarscout::test::all_expected()) {
        if (!e.json->contains("laz") || e.json->at("laz").is_null()) continue;
        if (is_broken_on_purpose(e) == broken) out.push_back(std::move(e));
    }
    return out;
}

class LaszipVlrMatchesReference : public ::testing::TestWithParam<Expected> {};

TEST_P(LaszipVlrMatchesReference, SameCompressorChunkSizeAndItems) {
    const auto& x = GetParam().json->at("laz");
    const auto vlr = laszip_of(GetParam().file);
    EXPECT_EQ(vlr.compressor, x.at("compressor").get<int>());
    EXPECT_EQ(vlr.coder, 0);
    EXPECT_EQ(vlr.chunk_size, x.at("chunk_size").get<std::uint32_t>());
    const auto& items = x.at("items");
    ASSERT_EQ(vlr.items.size(), items.size());
    for (std::size_t i = 0; i < items.size(); ++i) {
        SCOPED_TRACE("item " + std::to_string(i));
        EXPECT_EQ(vlr.items[i].type, items[i].at("type").get<int>());
        EXPECT_EQ(vlr.items[i].size, items[i].at("size").get<int>());
        EXPECT_EQ(vlr.items[i].version, items[i].at("version").get<int>());
        EXPECT_STREQ(item_type_name(vlr.items[i].type), items[i].at("name").get<std::string>().c_str());
    }
}

INSTANTIATE_TEST_SUITE_P(Formats, LaszipVlrMatchesReference, ::testing::ValuesIn(files_with_laz(false)), readable);

TEST(LaszipVlrFormats, ReferenceCoversAllLazFiles) { EXPECT_EQ(files_with_laz(false).size(), 74u); }

// LASzip's broken_*.laz: each has one defect, which the message must name.
class LaszipVlrBrokenFile : public ::testing::TestWithParam<Expected> {};

TEST_P(LaszipVlrBrokenFile, RejectedNamingTheDefect) {
    static const std::map<std::string, std::string> defect = {
        {"LASzip__LASzip__data__broken_coder.laz.json", "unknown coder 15"},
        {"LASzip__LASzip__data__broken_compressor.laz.json", "unknown compressor 16"},
        {"LASzip__LASzip__data__broken_size.laz.json", "item 0 (POINT10) has unsupported version 6"},
        {"LASzip__LASzip__data__broken_type.laz.json", "item 1 has unknown type 22"},
    };
    const auto& e = GetParam();
    ASSERT_TRUE(defect.count(e.name)) << "no expectation for " << e.name;
    try {
        laszip_of(e.file);
        FAIL() << "accepted";
    } catch (const Error& err) {
        EXPECT_NE(std::string(err.what()).find(defect.at(e.name)), std::string::npos) << err.what();
        EXPECT_EQ(err.file(), e.file.string());
        EXPECT_TRUE(err.offset().has_value());
    }
}

INSTANTIATE_TEST_SUITE_P(Broken, LaszipVlrBrokenFile, ::testing::ValuesIn(files_with_laz(true)), readable);

TEST(LaszipVlrFormats, AllFourBrokenFilesAreTested) { EXPECT_EQ(files_with_laz(true).size(), 4u); }

// ---- hand-made payloads ----------------------------------------------------------------------

struct Item {
    std::uint16_t type, size, version;
};

std::vector<std::uint8_t> payload(std::uint16_t compressor, const std::vector<Item>& items,
                                  std::uint32_t chunk_size = 50000, std::uint16_t coder = 0) {
    std::vector<std::uint8_t> p;
    auto put = [&](std::uint64_t v, int bytes) {
        for (int i = 0; i < bytes; ++i) p.push_back(static_cast<std::uint8_t>(v >> (8 * i)));
    };
    put(compressor, 2);
    put(coder, 2);
    put(3, 1);  // version 3.4r3
    put(4, 1);
    put(3, 2);
    put(0, 4);  // options
    put(chunk_size, 4);
    put(~0ull, 8);  // special EVLRs: none
    put(~0ull, 8);
    put(items.size(), 2);
    for (const auto& it : items) {
        put(it.type, 2);
        put(it.size, 2);
        put(it.version, 2);
    }
    return p;
}

constexpr std::uint64_t kAt = 1000;  // pretend file offset of the payload

LaszipVlr parse(const std::vector<std::uint8_t>& p) { return parse_laszip_vlr(p, "test.laz", kAt); }

// The message of the Error that parsing `p` throws ("" if it does not throw).
std::string rejection(const std::vector<std::uint8_t>& p, std::uint64_t* offset = nullptr) {
    try {
        parse(p);
    } catch (const Error& e) {
        if (offset && e.offset()) *offset = *e.offset();
        return e.cause();
    }
    return "";
}

TEST(LaszipVlrPayload, ParsesEveryField) {
    auto p = payload(3, {{10, 30, 3}, {11, 6, 3}, {14, 5, 3}}, 0xFFFFFFFFu);
    p[8] = 0x07;  // options = 7
    const auto v = parse(p);
    EXPECT_EQ(v.compressor, 3);
    EXPECT_EQ(v.version_major, 3);
    EXPECT_EQ(v.version_minor, 4);
    EXPECT_EQ(v.version_revision, 3);
    EXPECT_EQ(v.options, 7u);
    EXPECT_TRUE(v.variable_chunks());
    EXPECT_TRUE(v.chunked());
    EXPECT_EQ(v.number_of_special_evlrs, -1);
    EXPECT_EQ(v.offset_to_special_evlrs, -1);
    ASSERT_EQ(v.items.size(), 3u);
    EXPECT_EQ(v.items[2].type, 14);
    EXPECT_EQ(v.items[2].size, 5);
    EXPECT_EQ(v.record_length(), 41u);
}

TEST(LaszipVlrPayload, AcceptsEveryKnownItemVersion) {
    for (std::uint16_t v : {1, 2}) {
        EXPECT_EQ(rejection(payload(2, {{6, 20, v}, {7, 8, v}, {8, 6, v}, {0, 3, v}})), "") << v;
    }
    EXPECT_EQ(rejection(payload(2, {{6, 20, 2}, {7, 8, 2}, {9, 29, 1}})), "");
    for (std::uint16_t v : {2, 3, 4}) {
        EXPECT_EQ(rejection(payload(3, {{10, 30, v}, {12, 8, v}, {14, 1, v}})), "") << v;
        EXPECT_EQ(rejection(payload(3, {{10, 30, v}, {11, 6, v}})), "") << v;
    }
    EXPECT_EQ(rejection(payload(3, {{10, 30, 3}, {13, 29, 3}})), "");
    EXPECT_EQ(rejection(payload(3, {{10, 30, 4}, {13, 29, 4}})), "");
    EXPECT_EQ(rejection(payload(1, {{6, 20, 1}})), "");
}

TEST(LaszipVlrPayload, RejectsUnknownCompressorAndCoder) {
    std::uint64_t at = 0;
    EXPECT_EQ(rejection(payload(4, {{6, 20, 2}}), &at), "laszip VLR: unknown compressor 4");
    EXPECT_EQ(at, kAt);
    EXPECT_EQ(rejection(payload(2, {{6, 20, 2}}, 50000, 1), &at), "laszip VLR: unknown coder 1");
    EXPECT_EQ(at, kAt + 2);
}

TEST(LaszipVlrPayload, RejectsWrongPayloadSizes) {
    auto p = payload(2, {{6, 20, 2}, {7, 8, 2}});
    EXPECT_NE(rejection({p.begin(), p.begin() + 20}).find("shorter than the 34-byte fixed part"), std::string::npos);
    auto longer = p;
    longer.push_back(0);
    EXPECT_NE(rejection(longer).find("payload has 47 bytes but 2 items need 46"), std::string::npos);
    EXPECT_NE(rejection({p.begin(), p.end() - 6}).find("payload has 40 bytes but 2 items need 46"), std::string::npos);
    EXPECT_NE(rejection(payload(2, {})).find("no items"), std::string::npos);
}

TEST(LaszipVlrPayload, RejectsWrongItemSizes) {
    std::uint64_t at = 0;
    EXPECT_EQ(rejection(payload(2, {{6, 21, 2}}), &at), "laszip VLR: item 0 (POINT10) has size 21, must be 20");
    EXPECT_EQ(at, kAt + 34 + 2);
    EXPECT_NE(rejection(payload(2, {{6, 20, 2}, {7, 4, 2}})).find("GPSTIME11) has size 4, must be 8"),
              std::string::npos);
    EXPECT_NE(rejection(payload(2, {{6, 20, 2}, {8, 8, 2}})).find("RGB12) has size 8, must be 6"), std::string::npos);
    EXPECT_NE(rejection(payload(2, {{6, 20, 2}, {9, 28, 1}})).find("WAVEPACKET13) has size 28"), std::string::npos);
    EXPECT_NE(rejection(payload(2, {{6, 20, 2}, {0, 0, 2}})).find("(BYTE) has size 0"), std::string::npos);
    EXPECT_NE(rejection(payload(3, {{10, 20, 3}})).find("POINT14) has size 20, must be 30"), std::string::npos);
    EXPECT_NE(rejection(payload(3, {{10, 30, 3}, {12, 6, 3}})).find("RGBNIR14) has size 6, must be 8"),
              std::string::npos);
    EXPECT_NE(rejection(payload(3, {{10, 30, 3}, {14, 0, 3}})).find("(BYTE14) has size 0"), std::string::npos);
}

TEST(LaszipVlrPayload, RejectsUnsupportedItemVersions) {
    std::uint64_t at = 0;
    EXPECT_EQ(rejection(payload(2, {{6, 20, 0}}), &at),
              "laszip VLR: item 0 (POINT10) has unsupported version 0 (1 to 2 expected)");
    EXPECT_EQ(at, kAt + 34 + 4);
    EXPECT_NE(rejection(payload(2, {{6, 20, 3}})).find("version 3 (1 to 2 expected)"), std::string::npos);
    EXPECT_NE(
        rejection(payload(2, {{6, 20, 2}, {9, 29, 2}})).find("WAVEPACKET13) has unsupported version 2 (1 expected)"),
        std::string::npos);
    EXPECT_NE(rejection(payload(3, {{10, 30, 1}})).find("POINT14) has unsupported version 1 (2 to 4 expected)"),
              std::string::npos);
    EXPECT_NE(rejection(payload(3, {{10, 30, 5}})).find("version 5"), std::string::npos);
    EXPECT_NE(rejection(payload(3, {{10, 30, 3}, {13, 29, 2}})).find("WAVEPACKET14) has unsupported version 2 (3 to 4"),
              std::string::npos);
}

TEST(LaszipVlrPayload, RejectsUnknownItemTypes) {
    for (std::uint16_t type : {1, 2, 3, 4, 5, 15, 22, 0xFFFF}) {
        EXPECT_NE(
            rejection(payload(2, {{6, 20, 2}, {type, 4, 2}})).find("item 1 has unknown type " + std::to_string(type)),
            std::string::npos)
            << type;
    }
}

TEST(LaszipVlrPayload, RejectsItemListsNoDecoderHandles) {
    EXPECT_NE(rejection(payload(2, {{7, 8, 2}, {6, 20, 2}})).find("the first item is GPSTIME11"), std::string::npos);
    EXPECT_NE(rejection(payload(2, {{6, 20, 2}, {6, 20, 2}})).find("item 1 (POINT10) cannot follow POINT10"),
              std::string::npos);
    EXPECT_NE(rejection(payload(3, {{10, 30, 3}, {8, 6, 2}})).find("item 1 (RGB12) cannot follow POINT14"),
              std::string::npos);
    EXPECT_NE(rejection(payload(2, {{6, 20, 2}, {11, 6, 3}})).find("item 1 (RGB14) cannot follow POINT10"),
              std::string::npos);
    EXPECT_NE(rejection(payload(3, {{6, 20, 2}})).find("compressor 3 needs POINT14 items"), std::string::npos);
    EXPECT_NE(rejection(payload(2, {{10, 30, 3}})).find("compressor 2 cannot code POINT14 items"), std::string::npos);
}

TEST(LaszipVlrPayload, ItemTypeNames) {
    EXPECT_STREQ(item_type_name(0), "BYTE");
    EXPECT_STREQ(item_type_name(6), "POINT10");
    EXPECT_STREQ(item_type_name(12), "RGBNIR14");
    EXPECT_STREQ(item_type_name(14), "BYTE14");
    EXPECT_STREQ(item_type_name(15), "UNKNOWN");
}

}  // namespace
}  // namespace lidarscout::las
