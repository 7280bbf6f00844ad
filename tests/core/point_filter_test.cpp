// PointFilter: the options parsed (and refused with their range), return kinds, the description,
// presets; and per-class and per-return counts of real IGN tiles (format 6, classes 1-9, up to
// several returns a pulse) against a brute-force pass written out field by field, with filters
// keeping what the brute force keeps.
#include "core/point_filter.hpp"

#include <gtest/gtest.h>

#include "core/error.hpp"
#include "core/thread_pool.hpp"
#include "dataset/point_reader.hpp"
#include "dataset/tile.hpp"
#include "io/file.hpp"
#include "las/point_format.hpp"
#include "test_data.hpp"

namespace lidarscout {
using dataset::for_each_record_batch;
using dataset::read_tile;

namespace {

TEST(PointFilter, ParsesClassesReturnsAndIntensity) {
    const auto f = PointFilter::parse("2, 9,3-5", "last,single", "10-200");
    EXPECT_EQ(f.class_list(), "2-5,9");
    EXPECT_TRUE(f.keeps_class(4));
    EXPECT_FALSE(f.keeps_class(6));
    EXPECT_EQ(f.return_kinds, returns::kLast | returns::kSingle);
    EXPECT_EQ(f.intensity_min, 10);
    EXPECT_EQ(f.intensity_max, 200);
    EXPECT_EQ(f.describe(), "classes 2-5,9; last,single returns; intensity 10-200");
    EXPECT_EQ(PointFilter::parse("", "", "").describe(), "all points");
    EXPECT_TRUE(PointFilter::parse("0-255", "", "-").keeps_everything());
    EXPECT_EQ(PointFilter::parse("", "", "100-").intensity_max, 65535);
    EXPECT_EQ(PointFilter::parse("255", "", "").class_list(), "255");
}

TEST(PointFilter, RefusesWhatItCannotMeanWithTheRange) {
    for (const char* classes : {"256", "2,", "a", "5-3", "1-2-3", "-1"}) {
        try {
            PointFilter::parse(classes, "", "");
            ADD_FAILURE() << classes << " was accepted";
        } catch (const Error& e) {
            EXPECT_NE(std::string(e.what()).find("--classes expects class codes 0-255"), std::string::npos);
        }
    }
    EXPECT_THROW(PointFilter::parse("", "lastt", ""), Error);
    EXPECT_THROW(PointFilter::parse("", "", "300-200"), Error);
    EXPECT_THROW(PointFilter::parse("", "", "70000"), Error);
    EXPECT_THROW(PointFilter::parse("", "", "5"), Error);
}

TEST(PointFilter, ReturnKinds) {
    using namespace returns;
    EXPECT_EQ(kinds_of(1, 1), kFirst | kLast | kSingle);
    EXPECT_EQ(kinds_of(1, 3), kFirst);
    EXPECT_EQ(kinds_of(2, 3), kIntermediate);
    EXPECT_EQ(kinds_of(3, 3), kLast);
    EXPECT_EQ(kinds_of(0, 0), kFirst | kLast | kSingle);  // invalid zeros count as 1
    EXPECT_EQ(kinds_of(4, 2), kLast);                     // a count below its number
    const auto last = PointFilter::parse("", "last", "");
    EXPECT_TRUE(last.keeps_returns(2, 2));
    EXPECT_FALSE(last.keeps_returns(1, 2));
}

TEST(PointFilter, Presets) {
    ASSERT_GE(filter_presets().size(), 5u);
    EXPECT_EQ(filter_presets()[1].name, "Ground");
    EXPECT_EQ(filter_presets()[1].filter.class_list(), "2");
}

struct BruteCounts {
    std::array<std::uint64_t, 256> by_class{};
    std::uint64_t first = 0, last = 0, single = 0, intermediate = 0;
    std::uint64_t kept = 0;  // what the case's filter keeps, tested field by field
};

// A tile and a filter with its brute-force twin.
struct FilterCase {
    std::string name, file, classes, returns, intensity;
    bool (*keeps)(const las::Point& p);
};

class PointFilterOnTiles : public ::testing::TestWithParam<FilterCase> {};

TEST_P(PointFilterOnTiles, CountsAndKeepsMatchABruteForcePass) {
    const FilterCase& c = GetParam();
    auto file = io::File::open((test::surveys_dir() / c.file).string());
    const auto tile = read_tile(file);
    const auto& format = las::point_format_info(tile.header.point_format);
    ThreadPool pool(2);
    PointCounts counts;
    BruteCounts brute;
    std::uint64_t kept = 0;
    const auto filter = PointFilter::parse(c.classes, c.returns, c.intensity);
    for_each_record_batch(file, tile, pool, [&](std::uint64_t, std::span<const std::uint8_t> records) {
        for (std::size_t at = 0; at < records.size(); at += tile.header.record_length) {
            const auto p = las::decode_point(records.subspan(at, tile.header.record_length), format, tile.header);
            counts.add(p);
            kept += filter.keeps(p);
            ++brute.by_class[p.classification];
            const int r = p.return_number, n = p.number_of_returns;
            brute.first += r <= 1;
            brute.last += r >= n;
            brute.single += n <= 1;
            brute.intermediate += r > 1 && r < n;
            brute.kept += c.keeps(p);
        }
    });
    EXPECT_EQ(counts.total, tile.header.point_count);
    EXPECT_EQ(counts.by_class, brute.by_class);
    EXPECT_EQ(counts.first, brute.first);
    EXPECT_EQ(counts.last, brute.last);
    EXPECT_EQ(counts.single, brute.single);
    EXPECT_EQ(counts.intermediate, brute.intermediate);
    EXPECT_EQ(kept, brute.kept);
    EXPECT_GT(kept, 0u);                                 // the filter keeps some points ...
    EXPECT_LT(kept, counts.total);                       // ... and leaves some out
    EXPECT_GT(counts.intermediate + counts.single, 0u);  // the tile has several return kinds
}

INSTANTIATE_TEST_SUITE_P(
    Surveys, PointFilterOnTiles,
    ::testing::Values(
        // IGN (format 6): classes 1-5 with several returns per pulse
        FilterCase{"IgnVegetationFirst", "ign-lidar-hd-1km/Semis_2022_0906_6665_LA93_IGN69_ok.laz", "3-5", "first", "",
                   [](const las::Point& p) {
                       return p.classification >= 3 && p.classification <= 5 && p.return_number <= 1;
                   }},
        FilterCase{"IgnGroundOrLastBright", "ign-lidar-hd-1km/Semis_2022_0906_6665_LA93_IGN69_ok.laz", "",
                   "last,intermediate", "500-",
                   [](const las::Point& p) {
                       const bool last = p.return_number >= p.number_of_returns;
                       const bool mid = p.return_number > 1 && p.return_number < p.number_of_returns;
                       return (last || mid) && p.intensity >= 500;
                   }},
        FilterCase{"IgnGroundAndWaterSingleDim", "ign-lidar-hd-1km/test_semis_2021_0382_6565_LA93_IGN69.laz", "2,9",
                   "single", "-800",
                   [](const las::Point& p) {
                       return (p.classification == 2 || p.classification == 9) && p.number_of_returns <= 1 &&
                              p.intensity <= 800;
                   }}),
    [](const auto& info) { return info.param.name; });

}  // namespace
}  // namespace lidarscout
