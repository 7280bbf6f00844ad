// The whole formats/ corpus: every file is either read or rejected with a clear error naming
// the file, exactly as its row in INDEX.md says; and read with its records shared
// (SharedRecords), every file has the records it has alone, while a survey's tiles share one.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>

#include "core/error.hpp"
#include "dataset/tile.hpp"
#include "io/file.hpp"
#include "test_data.hpp"

namespace lidarscout {
namespace {

struct IndexRow {
    std::string file;
    bool decodes;
};

std::vector<IndexRow> index_rows() {
    std::vector<IndexRow> rows;
    for (const auto& [name, ok] : test::index_outcomes()) rows.push_back({name, ok});
    return rows;
}

class FormatsCorpus : public ::testing::TestWithParam<IndexRow> {};

TEST_P(FormatsCorpus, ReadOrRejectAsIndexSays) {
    const auto& row = GetParam();
    const std::string path = (test::formats_dir() / row.file).string();
    std::string error;
    try {
        auto file = io::File::open(path);
        auto tile = dataset::read_tile(file);
        EXPECT_EQ(tile.path(), path);
    } catch (const Error& e) {
        error = e.what();
        EXPECT_EQ(e.file(), path);
        EXPECT_EQ(error.find('\n'), std::string::npos) << "an error is one line";
        EXPECT_GT(e.cause().size(), 10u);
    }
    if (row.decodes) EXPECT_EQ(error, "") << row.file;
    else EXPECT_NE(error, "") << row.file << " must be rejected";
}

std::string row_name(const ::testing::TestParamInfo<IndexRow>& info) {
    std::string s = info.param.file;
    for (char& c : s) if (!std::isalnum(static_cast<unsigned char>(c))) c = '_';
    return s;
}

INSTANTIATE_TEST_SUITE_P(Index, FormatsCorpus, ::testing::ValuesIn(index_rows()), row_name);

TEST(FormatsCorpusIndex, ListsEveryFile) {
    auto rows = index_rows();
    EXPECT_EQ(rows.size(), 155u);
    std::size_t on_disk = 0;
    for (const auto& e : std::filesystem::recursive_directory_iterator(test::formats_dir())) {
        const bool expected_output = e.path().parent_path().filename() == "expected";
        if (e.is_regular_file() && !expected_output && e.path().filename() != "INDEX.md") ++on_disk;
    }
    EXPECT_EQ(on_disk, rows.size());
}

// Two CRSs say the same (an unknown factor, NaN, is the same as another unknown one).
void expect_same_crs(const las::Crs& a, const las::Crs& b, const std::string& file) {
    const auto same = [](double x, double y) { return x == y || (std::isnan(x) && std::isnan(y)); };
    EXPECT_EQ(a.source, b.source) << file;
    EXPECT_EQ(a.epsg, b.epsg) << file;
    EXPECT_EQ(a.vertical_epsg, b.vertical_epsg) << file;
    EXPECT_EQ(a.vertical_usable, b.vertical_usable) << file;
    EXPECT_EQ(a.name, b.name) << file;
    EXPECT_EQ(a.geographic, b.geographic) << file;
    EXPECT_EQ(a.horizontal_unit, b.horizontal_unit) << file;
    EXPECT_EQ(a.vertical_unit, b.vertical_unit) << file;
    EXPECT_TRUE(same(a.horizontal_to_metres, b.horizontal_to_metres)) << file;
    EXPECT_TRUE(same(a.vertical_to_metres, b.vertical_to_metres)) << file;
    EXPECT_EQ(a.horizontal_unit_name, b.horizontal_unit_name) << file;
    EXPECT_EQ(a.vertical_unit_name, b.vertical_unit_name) << file;
    EXPECT_EQ(a.wkt, b.wkt) << file;
    EXPECT_EQ(a.warnings, b.warnings) << file;
}

TEST(SharedRecords, EveryFileKeepsItsOwnRecords) {
    dataset::SharedRecords shared;
    dataset::TileOptions options;
    options.shared_records = &shared;
    std::size_t tiles = 0;
    for (const auto& root : {test::formats_dir(), test::surveys_dir()}) {
        for (const auto& e : std::filesystem::recursive_directory_iterator(root)) {
            const std::string path = e.path().string();
            if (!e.is_regular_file() || (e.path().extension() != ".las" && e.path().extension() != ".laz")) continue;
            try {
                const auto file = io::File::open(path);
                const auto alone = dataset::read_tile(file);
                const auto sharing = dataset::read_tile(file, options);
                ++tiles;
                EXPECT_EQ(sharing.vlrs(), alone.vlrs()) << path;
                EXPECT_EQ(sharing.evlrs(), alone.evlrs()) << path;
                EXPECT_EQ(sharing.laz(), alone.laz()) << path;
                expect_same_crs(sharing.crs(), alone.crs(), path);
            } catch (const Error&) {
                // rejected files are the corpus test's business
            }
        }
    }
    EXPECT_GT(tiles, 100u);
    EXPECT_LT(shared.size(), tiles) << "alike records (a survey's tiles) are shared";
}

TEST(SharedRecords, ASurveysTilesShareOneRecords) {
    dataset::SharedRecords shared;
    dataset::TileOptions options;
    options.shared_records = &shared;
    std::vector<dataset::Tile> tiles;
    for (const auto& e : std::filesystem::directory_iterator(test::surveys_dir() / "ky-jmo335-eastern-kentucky")) {
        if (e.path().extension() != ".laz") continue;
        tiles.push_back(dataset::read_tile(io::File::open(e.path().string()), options));
    }
    ASSERT_EQ(tiles.size(), 9u);
    for (std::size_t i = 1; i < tiles.size(); ++i) {
        EXPECT_EQ(tiles[i].file->records, tiles[0].file->records) << tiles[i].path();
        EXPECT_NE(tiles[i].file, tiles[0].file) << "each file keeps its own path and chunk table";
    }
    EXPECT_EQ(shared.size(), 1u);
}

// Records differ with the WKT bit (it picks the CRS record), and an EVLR left on disk is never shared.
TEST(SharedRecords, TheWktBitAndUnloadedEvlrsKeepRecordsApart) {
    const auto path = (test::surveys_dir() / "ky-jmo335-eastern-kentucky/N117E379.laz").string();
    const auto records = dataset::read_tile(io::File::open(path)).file->records;
    dataset::SharedRecords shared;
    const auto a = shared.intern(std::make_shared<dataset::TileRecords>(*records), false);
    EXPECT_EQ(shared.intern(std::make_shared<dataset::TileRecords>(*records), false), a);
    EXPECT_NE(shared.intern(std::make_shared<dataset::TileRecords>(*records), true), a);
    auto big = std::make_shared<dataset::TileRecords>(*records);
    big->evlrs.push_back({"big", 7, "", true, 1000, 1060, 8u << 20, false, {}});
    const auto b = shared.intern(big, false);
    EXPECT_EQ(b, big);
    EXPECT_NE(shared.intern(std::make_shared<dataset::TileRecords>(*big), false), b);
    EXPECT_EQ(shared.size(), 2u);
}

// find gives the records of the same VLRs, EVLRs and WKT bit, and only where their CRS came without a warning
// (a tile reading its CRS would get the same); read_tile then skips its CRS read.
TEST(SharedRecords, FindGivesRecordsWhoseCrsCameWithoutWarning) {
    const auto path = (test::surveys_dir() / "ky-jmo335-eastern-kentucky/N117E379.laz").string();
    const auto records = dataset::read_tile(io::File::open(path)).file->records;
    ASSERT_TRUE(records->crs.warnings.empty());
    dataset::SharedRecords shared;
    EXPECT_EQ(shared.find(records->vlrs, records->evlrs, false), nullptr) << "nothing given yet";
    const auto a = shared.intern(std::make_shared<dataset::TileRecords>(*records), false);
    EXPECT_EQ(shared.find(records->vlrs, records->evlrs, false), a);
    EXPECT_EQ(shared.find(records->vlrs, records->evlrs, true), nullptr) << "the WKT bit picks the CRS record";
    auto other_vlrs = records->vlrs;
    other_vlrs.back().data.push_back(0);
    EXPECT_EQ(shared.find(other_vlrs, records->evlrs, false), nullptr);
    auto unloaded = records->evlrs;
    unloaded.push_back({"big", 7, "", true, 1000, 1060, 8u << 20, false, {}});
    EXPECT_EQ(shared.find(records->vlrs, unloaded, false), nullptr) << "an EVLR on disk: its CRS is read";

    auto warned = std::make_shared<dataset::TileRecords>(*records);
    warned->crs.warnings.warn("a warning naming its file");
    dataset::SharedRecords with_warning;
    EXPECT_EQ(with_warning.intern(warned, false), warned);
    EXPECT_EQ(with_warning.find(records->vlrs, records->evlrs, false), nullptr)
        << "a CRS warning names the file it came from: another file reads its own";

    dataset::TileOptions options;
    options.shared_records = &shared;
    const auto tile = dataset::read_tile(io::File::open(path), options);
    EXPECT_EQ(tile.file->records, a) << "the tile takes the records found";
}

}  // namespace
}  // namespace lidarscout
