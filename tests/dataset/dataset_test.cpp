// open_dataset: folders, tile lists and several paths; bounds in metres (Kentucky tiles are
// in US survey feet); bad files skipped with one line naming them while the rest is read;
// tiles in a CRS other than the majority's (or the one asked for) reprojected into it, landing
// where they belong; each tile reported as it is read, and an opening cancelled half-way; a
// tile whose compound CRS PROJ lacks the vertical part of is placed by its horizontal part. A tile
// named many times (catalog items, a `next` loop, arguments, a list, links) is read once, with one
// warning; a virtual replica's tiles sharing a file are all kept; a FIFO named anywhere is one
// line, not a hang.
#include <gtest/gtest.h>
#include <sys/stat.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <mutex>
#include <vector>
#include <filesystem>
#include <fstream>

#include <nlohmann/json.hpp>

#include "core/error.hpp"
#include "core/thread_pool.hpp"
#include "dataset/dataset.hpp"
#include "dataset/file_search.hpp"
#include "dataset/point_stream.hpp"
#include "dataset/stac_catalog.hpp"
#include "dataset/virtual_replica.hpp"
#include "geo/projection.hpp"
#include "las_fixture.hpp"
#include "temp_dir_fixture.hpp"
#include "test_data.hpp"

namespace lidarscout::dataset {
namespace {

namespace fs = std::filesystem;

fs::path temp_dir(const std::string& name) {
    auto dir = fs::temp_directory_path() / ("lidarscout_dataset_test_" + name + "_" + std::to_string(::getpid()));
    fs::remove_all(dir);
    fs::create_directories(dir);
    return dir;
}

TEST(Dataset, SurveyFolderBoundsInMetres) {
    const auto folder = test::surveys_dir() / "ky-jmo335-eastern-kentucky";
    const Dataset ds = open_dataset({folder.string()});
    ASSERT_TRUE(ds.skipped.empty());
    ASSERT_EQ(ds.tiles.size(), find_point_cloud_files({folder.string()}).files.size());
    constexpr double kFt = 1200.0 / 3937.0;
    Bounds expected;
    for (const auto& t : ds.tiles) {
        SCOPED_TRACE(t.tile.path());
        EXPECT_DOUBLE_EQ(t.xy_to_metres, kFt);
        EXPECT_DOUBLE_EQ(t.bounds_m.min_x, t.tile.header.min[0] * kFt);
        EXPECT_DOUBLE_EQ(t.bounds_m.max_y, t.tile.header.max[1] * kFt);
        EXPECT_DOUBLE_EQ(t.bounds_m.max_z, t.tile.header.max[2] * kFt);
        EXPECT_GT(t.chunk_points, 0u);
        expected.extend(t.bounds_m);
    }
    EXPECT_EQ(ds.bounds_m.min_x, expected.min_x);
    EXPECT_EQ(ds.bounds_m.max_y, expected.max_y);
    EXPECT_TRUE(ds.warnings.empty());
}

TEST(Dataset, MetreSurveyKeepsCoordinates) {
    const Dataset ds = open_dataset({(test::surveys_dir() / "ign-lidar-hd-1km").string()});
    ASSERT_FALSE(ds.tiles.empty());
    for (const auto& t : ds.tiles) {
        EXPECT_EQ(t.xy_to_metres, 1.0);
        EXPECT_EQ(t.bounds_m.min_x, t.tile.header.min[0]);
    }
}

TEST(Dataset, MixedCrsWarns) {
    const Dataset ds = open_dataset({(test::surveys_dir() / "ky-woodford-county").string(),
                                     (test::surveys_dir() / "ign-lidar-hd-1km").string()});
    ASSERT_TRUE(ds.skipped.empty());
    // Two warnings: the mix, and NAD83 -> RGF93 being only a ballpark shift without a grid.
    ASSERT_EQ(ds.warnings.size(), 2u);
    const auto mix = std::find_if(ds.warnings.begin(), ds.warnings.end(), [](const Diagnostic& d) {
        return d.message.find("different coordinate reference systems") != std::string::npos;
    });
    ASSERT_NE(mix, ds.warnings.end());
    EXPECT_EQ(mix->level, DiagnosticLevel::warning);
    EXPECT_NE(mix->message.find("EPSG:3089"), std::string::npos);
    EXPECT_NE(mix->message.find("reprojected to EPSG:2154"), std::string::npos);  // 7 IGN tiles, 1 Kentucky
    const auto ballpark = std::find_if(ds.warnings.begin(), ds.warnings.end(), [](const Diagnostic& d) {
        return d.message.find("ballpark transformation from EPSG:3089") != std::string::npos;
    });
    ASSERT_NE(ballpark, ds.warnings.end());
    EXPECT_NE(ballpark->file.find("ky-woodford-county"), std::string::npos);
    EXPECT_EQ(ds.frame.crs.rfind("EPSG:2154", 0), 0u);
}

TEST(Dataset, CompoundCrsWithAVerticalPartProjLacksKeepsEveryFile) {
    // 4_6_crop.las says EPSG:2903 + 5103, a vertical code PROJ lacks; test1_4.las (EPSG:2903 in
    // WKT) used to be skipped when the dataset's frame became the unusable compound.
    const std::string crop = (test::formats_dir() / "PDAL__PDAL" / "test__data__las__4_6_crop.las").string();
    const std::string wkt = (test::formats_dir() / "PDAL__PDAL" / "test__data__las__test1_4.las").string();
    const Dataset ds = open_dataset({crop, wkt});
    EXPECT_TRUE(ds.skipped.empty()) << ds.skipped.front().error;
    ASSERT_EQ(ds.tiles.size(), 2u);
    EXPECT_EQ(ds.frame.crs, "EPSG:2903");
    ASSERT_EQ(ds.warnings.size(), 1u);
    const Diagnostic& w = *ds.warnings.begin();
    EXPECT_EQ(w.file, crop);
    EXPECT_NE(w.message.find("vertical CRS EPSG:5103"), std::string::npos) << w.message;
    for (const auto& t : ds.tiles) {  // test1_4.las (EPSG:2903+5703) moves into EPSG:2903 where it is
        EXPECT_NEAR(t.bounds_m.min_x, t.tile.header.min[0] * t.xy_to_metres, 1e-3) << t.tile.path();
        EXPECT_NEAR(t.bounds_m.max_y, t.tile.header.max[1] * t.xy_to_metres, 1e-3) << t.tile.path();
    }
}

std::vector<MetricPoint> all_points(const Dataset& ds, std::uint32_t tile) {
    ThreadPool pool(2);
    std::vector<MetricPoint> out;
    for_each_metric_batch(ds, tile, pool, [&](std::uint64_t, std::span<const MetricPoint> p) {
        out.insert(out.end(), p.begin(), p.end());
    });
    return out;
}

// A real tile (UTM 32N) converted to UTM 33N and written with our LAS writer lands on its
// original place, point by point, once reprojected back into the dataset's CRS.
TEST(Dataset, TileInAnotherCrsLandsOnItsPlace) {
    const auto dir = temp_dir("reproject");
    const std::string original = (test::surveys_dir() / "isprs-filter-test-sites" / "CSite3_orig-utm.laz").string();
    const Dataset one = open_dataset({original});
    ASSERT_EQ(one.tiles.size(), 1u);
    EXPECT_EQ(one.frame.crs, "EPSG:32632");
    const auto points = all_points(one, 0);
    std::vector<double> x, y, z;
    for (const auto& p : points) x.push_back(p.x), y.push_back(p.y), z.push_back(p.z);
    geo::CrsTransform("EPSG:32632", "EPSG:32633").apply(x, y, {});
    std::vector<test::FixturePoint> moved;
    for (std::size_t i = 0; i < x.size(); ++i) moved.push_back({x[i], y[i], z[i]});
    ASSERT_GT(std::abs(moved[0].x - points[0].x), 100'000.0);  // zone 33 coordinates are far away
    const std::string converted = (dir / "zone33.las").string();
    test::write_fixture(converted, moved, 32633);

    DatasetOptions options;
    options.crs = "EPSG:32632";
    const Dataset both = open_dataset({converted, original}, options);
    ASSERT_EQ(both.tiles.size(), 2u);
    ASSERT_TRUE(both.tiles[0].to_frame);
    EXPECT_FALSE(both.tiles[1].to_frame);
    const auto& a = both.tiles[0].bounds_m, &b = both.tiles[1].bounds_m;
    // the converted box is rotated by the change of zone: its bounds enclose the original, a little larger
    EXPECT_LE(a.min_x, b.min_x + 0.01);
    EXPECT_LE(a.min_y, b.min_y + 0.01);
    EXPECT_GE(a.max_x, b.max_x - 0.01);
    EXPECT_GE(a.max_y, b.max_y - 0.01);
    EXPECT_LT(a.max_x - a.min_x, 1.25 * (b.max_x - b.min_x));  // ~4.4 degrees of grid convergence between the zones
    EXPECT_LT(a.max_y - a.min_y, 1.25 * (b.max_y - b.min_y));
    const auto back = all_points(both, 0);
    ASSERT_EQ(back.size(), points.size());
    double worst = 0;
    for (std::size_t i = 0; i < back.size(); ++i) {
        worst = std::max({worst, std::abs(back[i].x - points[i].x), std::abs(back[i].y - points[i].y)});
        ASSERT_NEAR(back[i].z, points[i].z, 0.0005);
    }
    EXPECT_LT(worst, 0.001);  // the writer's millimetre scale

    const std::string copy = (dir / "copy.laz").string();  // (not the original again: a tile named twice is one)
    fs::copy_file(original, copy);
    const Dataset majority = open_dataset({converted, original, copy});  // two tiles in 32632, one in 32633
    EXPECT_EQ(majority.frame.crs, "EPSG:32632");
    ASSERT_EQ(majority.warnings.size(), 1u);
    EXPECT_NE(majority.warnings[0].message.find("reprojected to EPSG:32632"), std::string::npos);
    fs::remove_all(dir);
}

// A tile in ETRS89 / UTM 32N + DHHN2016 height asked for in EVRF2007 heights: its heights move
// by the offset PROJ's database gives (+2.64 cm near 9 E, 48.75 N), bounds included, and nothing
// is said. Asked for in EGM96 heights (no grid installed for that), they stay, and a warning
// says the transformation is only a ballpark one. Without a vertical part asked for, heights
// keep the file's datum.
TEST(Dataset, HeightsMoveBetweenVerticalDatums) {
    const auto dir = temp_dir("vertical");
    std::vector<test::FixturePoint> points;
    for (int i = 0; i < 50; ++i) points.push_back({500'000.0 + 10 * i, 5'400'000.0 + 7 * i, 100.0 + i});
    const std::string tile = (dir / "dhhn2016.las").string();
    test::write_fixture(tile, points, 25832, false, 50'000, 7837);
    const auto open_as = [&](const std::string& crs) {
        DatasetOptions options;
        options.crs = crs;
        return open_dataset({tile}, options);
    };
    const Dataset own = open_dataset({tile});
    ASSERT_EQ(own.frame.crs, "EPSG:25832+7837");
    const Dataset evrf = open_as("EPSG:25832+5621");
    ASSERT_EQ(evrf.tiles.size(), 1u);
    EXPECT_TRUE(evrf.tiles[0].heights_to_frame);
    EXPECT_TRUE(evrf.warnings.empty());
    const auto a = all_points(own, 0), b = all_points(evrf, 0);
    ASSERT_EQ(a.size(), b.size());
    for (std::size_t i = 0; i < a.size(); ++i) {
        EXPECT_NEAR(b[i].z - a[i].z, 0.0264, 0.002);
        EXPECT_NEAR(b[i].x, a[i].x, 0.001);
    }
    EXPECT_NEAR(evrf.tiles[0].bounds_m.min_z - own.tiles[0].bounds_m.min_z, 0.0264, 0.002);
    EXPECT_NEAR(evrf.tiles[0].bounds_m.max_z - own.tiles[0].bounds_m.max_z, 0.0264, 0.002);

    const Dataset egm = open_as("EPSG:25832+5773");
    ASSERT_EQ(egm.warnings.size(), 1u);
    EXPECT_NE(egm.warnings[0].message.find("ballpark"), std::string::npos);
    EXPECT_EQ(egm.warnings[0].file, tile);
    EXPECT_NEAR(all_points(egm, 0)[0].z, a[0].z, 1e-9);

    const Dataset flat = open_as("EPSG:32632");  // horizontal only: heights as stored
    EXPECT_FALSE(flat.tiles[0].heights_to_frame);
    EXPECT_NEAR(all_points(flat, 0)[0].z, a[0].z, 1e-9);
    fs::remove_all(dir);
}

TEST(Dataset, UnknownCrsAskedForIsAnError) {
    DatasetOptions options;
    options.crs = "EPSG:999999";
    EXPECT_THROW(open_dataset({(test::surveys_dir() / "ky-red-river-gorge").string()}, options), Error);
    options.crs = "EPSG:4326";  // degrees: no metric patches
    EXPECT_THROW(open_dataset({(test::surveys_dir() / "ky-red-river-gorge").string()}, options), Error);
}

TEST(Dataset, TileListWithRelativeEntriesCommentsAndMissingFiles) {
    const auto dir = temp_dir("list");
    const auto ky = test::surveys_dir() / "ky-woodford-county";
    const auto ign = find_point_cloud_files({(test::surveys_dir() / "ign-lidar-hd-1km").string()}).files;
    ASSERT_GE(ign.size(), 2u);
    fs::create_directory_symlink(ky, dir / "ky");
    {
        std::ofstream list(dir / "tiles.txt");
        list << "# tiles for the test\n\n" << ign[0] << "\n  " << ign[1] << "  \nky\r\nmissing.laz\n";
    }
    ASSERT_TRUE(is_tile_list((dir / "tiles.txt").string()));
    const Dataset ds = open_dataset({(dir / "tiles.txt").string()});
    const auto ky_files = find_point_cloud_files({ky.string()}).files.size();
    EXPECT_EQ(ds.tiles.size(), 2 + ky_files);
    ASSERT_EQ(ds.skipped.size(), 1u);
    EXPECT_NE(ds.skipped[0].error.find("missing.laz"), std::string::npos);
    fs::remove_all(dir);
}

TEST(Dataset, BadFilesAreSkippedWithOneLineTheRestIsRead) {
    std::vector<std::string> paths;
    std::size_t bad = 0;
    for (const auto& [name, decodes] : test::index_outcomes()) {
        if (!decodes) {
            paths.push_back((test::formats_dir() / name).string());
            ++bad;
        }
    }
    ASSERT_GT(bad, 5u);
    paths.push_back((test::surveys_dir() / "ky-red-river-gorge").string());
    const Dataset ds = open_dataset(paths);
    EXPECT_GE(ds.tiles.size(), 1u);  // the survey tile (some "rejected" files fail only when decoding points)
    for (const auto& s : ds.skipped) {
        SCOPED_TRACE(s.error);
        EXPECT_EQ(s.error.find('\n'), std::string::npos);
        EXPECT_NE(s.error.find(fs::path(s.path).filename().string()), std::string::npos);
    }
    EXPECT_GT(ds.skipped.size(), bad / 2);
    bool survey_read = false;
    for (const auto& t : ds.tiles) survey_read |= t.tile.path().find("ky-red-river-gorge") != std::string::npos;
    EXPECT_TRUE(survey_read);
}

TEST(Dataset, EachTileReadIsReportedAsItArrives) {
    const auto folder = test::surveys_dir() / "ky-jmo335-eastern-kentucky";
    std::mutex mutex;
    std::vector<Bounds> reported;
    std::size_t last_done = 0;
    DatasetOptions options;
    options.tile_read = [&](const DatasetTile& t) {
        std::lock_guard lock(mutex);
        reported.push_back(t.bounds_m);
    };
    options.progress = [&](std::size_t done, std::size_t) {
        std::lock_guard lock(mutex);
        EXPECT_GE(reported.size(), done);  // each tile is reported before it is counted
        last_done = std::max(last_done, done);
    };
    const Dataset ds = open_dataset({folder.string()}, options);
    ASSERT_EQ(reported.size(), ds.tiles.size());
    EXPECT_EQ(last_done, ds.tiles.size());
    for (const auto& t : ds.tiles) {  // the same boxes, in any order
        const auto same = [&](const Bounds& b) { return b.min_x == t.bounds_m.min_x && b.min_y == t.bounds_m.min_y; };
        EXPECT_EQ(std::count_if(reported.begin(), reported.end(), same), 1) << t.tile.path();
    }
}

TEST(Dataset, CancelledOpeningStopsReadingAndThrows) {
    const auto folder = test::surveys_dir() / "ky-jmo335-eastern-kentucky";
    std::atomic<bool> cancel{false};
    std::atomic<std::size_t> read{0};
    DatasetOptions options;
    options.io_threads = 1;  // one file at a time: the cancel lands before the second
    options.cancel = &cancel;
    options.tile_read = [&](const DatasetTile&) {
        ++read;
        cancel = true;
    };
    try {
        open_dataset({folder.string()}, options);
        FAIL() << "a cancelled opening returned a dataset";
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find("cancelled"), std::string::npos) << e.what();
    }
    EXPECT_EQ(read.load(), 1u);
    EXPECT_GT(find_point_cloud_files({folder.string()}).files.size(), 1u);
}

TEST(Dataset, PatchGridOriginIsOnTheMetricLattice) {
    const Dataset ds = open_dataset({(test::surveys_dir() / "ky-red-river-gorge").string()});
    const auto [ox, oy] = patch_grid_origin(ds);
    EXPECT_EQ(std::fmod(ox, 640.0), 0.0);
    EXPECT_EQ(std::fmod(oy, 640.0), 0.0);
    EXPECT_LE(ox, ds.bounds_m.min_x);
    EXPECT_GT(ox + 640.0, ds.bounds_m.min_x);
    EXPECT_LE(oy, ds.bounds_m.min_y);
}

// A source that a catalog item places at [x0, x0 + 100] x [0, 100] (metres, EPSG:32632).
TileSource placed_source(const std::string& name, double x0) {
    auto item = std::make_shared<CatalogItem>();
    item->href = name, item->crs = "EPSG:32632";
    item->bbox = std::array<double, 6>{x0, 0, 0, x0 + 100, 100, 10};
    return {name, std::nullopt, "", item};
}

TEST(Dataset, CentralSourcesAreTheNearestToTheCatalogsCentre) {
    std::vector<TileSource> row;  // ten tiles in a row: 0-1000 m, the centre at 500 m
    for (int i = 0; i < 10; ++i) row.push_back(placed_source("t" + std::to_string(i), 100.0 * i));
    const auto central = [](const std::vector<TileSource>& s, double radius, std::size_t most) {
        return central_sources(s, catalog_footprints(s), radius, most);
    };
    const auto names = [](const std::vector<TileSource>& s) {
        std::vector<std::string> out;
        for (const auto& t : s) out.push_back(t.path);
        return out;
    };
    EXPECT_EQ(names(central(row, 0, 10)), (std::vector<std::string>{"t4", "t5"}));  // touching it
    EXPECT_EQ(names(central(row, 150, 10)), (std::vector<std::string>{"t4", "t5", "t3", "t6"}));
    EXPECT_EQ(central(row, 150, 3).size(), 3u);
    EXPECT_EQ(central(row, 1e6, 100).size(), 10u);
    row.push_back({"plain.laz", std::nullopt, "", nullptr});  // a tile no item places: no centre known
    EXPECT_TRUE(central(row, 1e6, 100).empty());
}

TEST(Dataset, BoundsDistance) {
    Bounds b;
    b.min_x = 0, b.max_x = 10, b.min_y = 0, b.max_y = 10, b.min_z = 0, b.max_z = 1;
    EXPECT_EQ(b.distance_xy(5, 5), 0.0);
    EXPECT_EQ(b.distance_xy(13, 5), 3.0);
    EXPECT_EQ(b.distance_xy(13, 14), 5.0);
    EXPECT_TRUE(Bounds{}.empty());
}

// Tiles named several times, and names that are not regular files.
class DatasetInputs : public test::TempDirTest {
protected:
    static constexpr std::size_t kPoints = 300;

    void SetUp() override {
        TempDirTest::SetUp();
        fs::create_directories(dir / "sub");
        write_tile("t.las", 500'000);
        write_tile("u.las", 501'000);
    }
    void write_tile(const char* name, double x0) {
        std::vector<test::FixturePoint> points;
        for (std::size_t i = 0; i < kPoints; ++i) points.push_back({x0 + double(i % 20), 5e6 + double(i / 20), 1.0});
        test::write_fixture(path(name), points, 32632);
    }
    // A STAC item whose data asset is `href`.
    static nlohmann::json item(const std::string& href) {
        return {{"type", "Feature"}, {"id", href}, {"properties", nlohmann::json::object()},
                {"assets", {{"data", {{"href", href}, {"roles", {"data"}}}}}}};
    }
    std::string write_json(const std::string& name, const nlohmann::json& doc) {
        std::ofstream(dir / name) << doc.dump(1);
        return (dir / name).string();
    }
    std::string write_text(const std::string& name, const std::string& text) {
        std::ofstream(dir / name) << text;
        return (dir / name).string();
    }
    // The one warning of `ds`, which must name the tiles named again.
    static std::string duplicates_warning(const Dataset& ds) {
        EXPECT_EQ(ds.warnings.size(), 1u);
        return ds.warnings.empty() ? std::string() : ds.warnings.front().message;
    }
};

TEST_F(DatasetInputs, ThreeCatalogItemsNamingOneTileReadItOnce) {
    const nlohmann::json items = {item("../t.las"), item(path("t.las")), item("../sub/../t.las"), item("../u.las")};
    const std::string catalog = write_json("sub/cat.json", {{"type", "FeatureCollection"}, {"features", items}});
    const Dataset ds = open_dataset({catalog});
    ASSERT_EQ(ds.tiles.size(), 2u);
    EXPECT_TRUE(ds.skipped.empty());
    EXPECT_EQ(ds.point_count, 2 * kPoints);
    const std::string warning = duplicates_warning(ds);
    EXPECT_NE(warning.find("2 inputs name tiles already named"), std::string::npos) << warning;
    EXPECT_NE(warning.find("t.las (3 times)"), std::string::npos) << warning;
    EXPECT_EQ(warning.find("u.las"), std::string::npos) << warning;
}

TEST_F(DatasetInputs, ArgumentsListsLinksAndHardLinksNamingOneTileReadItOnce) {
    fs::create_symlink(dir / "t.las", dir / "link.las");
    fs::create_hard_link(dir / "t.las", dir / "hard.las");
    const std::string list = write_text("tiles.txt", "t.las\n./t.las\nsub/../u.las\n");
    const Dataset ds = open_dataset({path("t.las"), path("t.las"), (dir / "sub" / ".." / "t.las").string(),
                                     path("link.las"), path("hard.las"), list, path("u.las")});
    ASSERT_EQ(ds.tiles.size(), 2u);
    EXPECT_EQ(ds.point_count, 2 * kPoints);
    EXPECT_EQ(ds.tiles[0].tile.path(), path("t.las")) << "the first name given is kept";
    const std::string warning = duplicates_warning(ds);
    EXPECT_NE(warning.find("7 inputs name tiles already named"), std::string::npos) << warning;
    // (u.las first named by the list, through sub/..)
    EXPECT_NE(warning.find("t.las (7 times), " + (dir / "sub/../u.las").string() + " (2 times)"), std::string::npos)
        << warning;
}

// A loop of `next` pages naming one tile (through two names) reads it once: the second page repeats
// the first's items, so the walk stops there with one line (stac_catalog.cpp), before any copy is counted.
TEST_F(DatasetInputs, ALoopOfNextPagesNamingOneTileReadsItOnce) {
    constexpr int kPages = 33;
    for (int i = 0; i < kPages; ++i) {  // page i names t.las and links page i + 1 (the last, page 0 again)
        const nlohmann::json next = {{"rel", "next"}, {"href", "page" + std::to_string((i + 1) % kPages) + ".json"}};
        write_json("page" + std::to_string(i) + ".json",
                   {{"type", "FeatureCollection"}, {"features", {item(i % 2 ? "./t.las" : "sub/../t.las")}},
                    {"links", {next}}});
    }
    const Dataset ds = open_dataset({path("page0.json")});
    ASSERT_EQ(ds.tiles.size(), 1u);
    EXPECT_EQ(ds.point_count, kPoints);
    std::string lines;
    for (const auto& s : ds.skipped) lines += s.error + "\n";
    for (const auto& w : ds.warnings) lines += w.message + "\n";
    EXPECT_NE(lines.find("repeats the items of page 1"), std::string::npos) << lines;
}

TEST_F(DatasetInputs, ManyTilesNamedAgainAreListedShort) {
    std::vector<std::string> paths;
    for (int i = 0; i < 12; ++i) {
        const std::string name = "c" + std::to_string(i) + ".las";
        fs::copy_file(dir / "t.las", dir / name);
        paths.push_back(path(name.c_str()));
        paths.push_back(path(name.c_str()));
    }
    const Dataset ds = open_dataset(paths);
    EXPECT_EQ(ds.tiles.size(), 12u);
    const std::string warning = duplicates_warning(ds);
    EXPECT_NE(warning.find("12 inputs name tiles already named"), std::string::npos) << warning;
    EXPECT_NE(warning.find("c4.las (2 times) and 7 more tiles"), std::string::npos) << warning;
    EXPECT_EQ(warning.find("c5.las"), std::string::npos) << warning;
}

TEST_F(DatasetInputs, AVirtualReplicasTilesSharingOneFileAreAllKept) {
    nlohmann::json tiles = nlohmann::json::array();
    for (int i = 0; i < 3; ++i) tiles.push_back({{"file", "v" + std::to_string(i) + ".las"}, {"source", 0},
                                                 {"shift", {1000.0 * i, 0.0}}});
    const std::string manifest = write_json(
        "replicate.json", {{"tool", kReplicaTool}, {"virtual", true}, {"sources", {{{"path", path("t.las")}}}},
                           {"tiles", tiles}});
    ASSERT_TRUE(is_virtual_replica(manifest));
    const Dataset once = open_dataset({manifest});
    ASSERT_EQ(once.tiles.size(), 3u) << "one file, three places: three tiles";
    EXPECT_TRUE(once.warnings.empty());
    const Dataset twice = open_dataset({manifest, manifest, path("t.las")});
    EXPECT_EQ(twice.tiles.size(), 4u) << "the replica's three once each, and the file itself";
    const std::string warning = duplicates_warning(twice);
    EXPECT_NE(warning.find("3 inputs name tiles already named"), std::string::npos) << warning;
    EXPECT_NE(warning.find("v1.las (2 times)"), std::string::npos) << warning;
}

// A FIFO named by a catalog item, a tile list entry, an argument, or as a catalog, list or manifest:
// one line each, the other tiles read. (Opening a FIFO to read it waits for a writer: this test ends
// only because nothing opens it so.)
TEST_F(DatasetInputs, AFifoNamedAnywhereIsOneLineAndNeverRead) {
    for (const char* name : {"pipe.laz", "pipe.json", "pipe.txt", "replicate-pipe/replicate.json"}) {
        fs::create_directories((dir / name).parent_path());
        ASSERT_EQ(::mkfifo(path(name).c_str(), 0600), 0) << name;
    }
    const std::string catalog =
        write_json("cat.json", {{"type", "FeatureCollection"}, {"features", {item("pipe.laz"), item("t.las")}}});
    const std::string list = write_text("list.txt", "pipe.laz\nt.las\n");
    for (const auto& paths : std::vector<std::vector<std::string>>{
             {catalog}, {list}, {path("pipe.laz"), path("t.las")}, {path("pipe.json"), path("t.las")},
             {path("pipe.txt"), path("t.las")}, {path("replicate-pipe/replicate.json"), path("t.las")}}) {
        SCOPED_TRACE(paths.front());
        const Dataset ds = open_dataset(paths);
        ASSERT_EQ(ds.tiles.size(), 1u);
        EXPECT_EQ(ds.tiles[0].tile.path(), path("t.las"));
        ASSERT_EQ(ds.skipped.size(), 1u);
        const std::string& line = ds.skipped[0].error;
        EXPECT_EQ(line.find('\n'), std::string::npos) << line;
        EXPECT_NE(line.find("pipe"), std::string::npos) << line;
        EXPECT_NE(line.find("is a FIFO (named pipe), not a regular file"), std::string::npos) << line;
    }
    const Dataset folder = open_dataset({path("replicate-pipe")});  // a folder of no tile, its "manifest" unread
    EXPECT_TRUE(folder.tiles.empty());
    EXPECT_EQ(folder.skipped.size(), 1u);
    EXPECT_FALSE(is_virtual_replica(path("replicate-pipe/replicate.json")));
    EXPECT_THROW(read_virtual_replica(path("replicate-pipe/replicate.json")), Error);
}

}  // namespace
}  // namespace lidarscout::dataset
