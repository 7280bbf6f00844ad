// Header and VLR serialisation reproduce the bytes of every readable corpus file.
#include <gtest/gtest.h>

#include "dataset/tile.hpp"
#include "io/file.hpp"
#include "las/header_writer.hpp"
#include "test_data.hpp"

namespace lidarscout {
namespace {

// Fixed-size strings are written NUL-padded: junk after a NUL in the original is not kept.
void clear_after_nul(std::vector<std::uint8_t>& b, std::size_t from, std::size_t size) {
    bool nul = false;
    for (std::size_t i = from; i < from + size && i < b.size(); ++i) {
        nul = nul || b[i] == 0;
        if (nul) b[i] = 0;
    }
}

std::vector<std::uint8_t> original_record(const io::File& file, const las::Vlr& v, std::size_t size) {
    auto orig = file.read_vector(v.header_offset, size);
    orig[0] = orig[1] = 0;  // the reserved field is written as zero
    clear_after_nul(orig, 2, 16);
    clear_after_nul(orig, v.extended ? 28 : 22, 32);
    return orig;
}

class HeaderRoundTrip : public ::testing::TestWithParam<std::string> {};

TEST_P(HeaderRoundTrip, SameBytes) {
    const auto path = (test::formats_dir() / GetParam()).string();
    auto file = io::File::open(path);
    auto tile = dataset::read_tile(file);
    const auto& h = tile.header;
    const auto standard = las::standard_header_size(h.version_major, h.version_minor);
    auto original = file.read_vector(0, h.header_size);
    clear_after_nul(original, 26, 32);
    clear_after_nul(original, 58, 32);
    std::vector<std::uint8_t> trailing(original.begin() + std::min<std::size_t>(standard, original.size()),
                                       original.end());
    auto bytes = las::serialize_header(h, trailing);
    ASSERT_EQ(bytes.size(), original.size());
    EXPECT_TRUE(bytes == original);
    for (const auto& v : tile.vlrs()) {
        auto rec = las::serialize_vlr(v);
        EXPECT_TRUE(rec == original_record(file, v, rec.size())) << "VLR " << v.user_id << " " << v.record_id;
    }
    for (const auto& v : tile.evlrs()) {
        if (!v.data_loaded) continue;
        auto rec = las::serialize_vlr(v);
        EXPECT_TRUE(rec == original_record(file, v, rec.size())) << "EVLR " << v.user_id << " " << v.record_id;
    }
}

std::vector<std::string> readable_files() {
    std::vector<std::string> out;
    for (const auto& [name, ok] : test::index_outcomes()) {
        if (ok) out.push_back(name);
    }
    return out;
}

INSTANTIATE_TEST_SUITE_P(Formats, HeaderRoundTrip, ::testing::ValuesIn(readable_files()),
                         [](const auto& info) {
                             std::string s = info.param;
                             for (char& c : s) if (!std::isalnum(static_cast<unsigned char>(c))) c = '_';
                             return s;
                         });

TEST(SetPointCount, LegacyAndExtended) {
    las::Header h;
    h.version_minor = 4;
    h.point_format = 3;
    las::set_point_count(h, 5'000'000'000ull);
    EXPECT_EQ(h.legacy_point_count, 0u);
    EXPECT_EQ(h.extended_point_count, 5'000'000'000ull);
    las::set_point_count(h, 100);
    EXPECT_EQ(h.legacy_point_count, 100u);
    h.point_format = 7;
    las::set_point_count(h, 100);
    EXPECT_EQ(h.legacy_point_count, 0u);
    EXPECT_EQ(h.point_count, 100u);
}

}  // namespace
}  // namespace lidarscout
