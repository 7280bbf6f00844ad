// `lidarscout clip` and `lidarscout profile` as a user runs them: --json counts, the output read back
// by `info`; a corrupt chunk named on one stderr line and skipped (exit 3); an output named like an
// input refused with the input unchanged; bad WKT, bad filters and a missing area as one-line errors
// (exit 1); a profile as CSV, LAZ and PNG with the same points; tiles in two UTM zones clipped with
// --crs written in that CRS, with a note; a tile named by three catalog items and twice as an argument
// clipped once, with one warning (which scan shows too); LAS 1.5 and wave packet files clipped to LAZ read
// back by `info` as such; waveform data refused on one line naming the file, nothing written, and with
// --force written with a note; a bow tie given as WKT or GeoJSON is clipped by the even-odd rule with one
// warning naming it and its crossing (issue 53), a square without one.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "core/sha256.hpp"
#include "damaged_tile.hpp"
#include "geo/projection.hpp"
#include "las_fixture.hpp"
#include "png_test_util.hpp"
#include "temp_dir_fixture.hpp"
#include "test_data.hpp"

namespace lidarscout {
namespace {

namespace fs = std::filesystem;

std::string read_text(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

class ClipCommand : public test::TempDirTest {
protected:
    static std::string woodford() {
        return (test::surveys_dir() / "ky-woodford-county" / "5205000_3900000.laz").string();
    }
    static std::string cli() { return std::string(LIDARSCOUT_CLI) + " "; }
    // The western half of the Woodford tile, in its CRS's US survey feet.
    static constexpr const char* kWest = " --bounds 5208000,3902900,5209000,3905100";
};

TEST_F(ClipCommand, JsonCountsAndTheOutputReadsBack) {
    std::string out;
    ASSERT_EQ(test::run_command(cli() + "clip " + woodford() + kWest + " --returns first -o " + path("west.laz") +
                                    " --json 2>/dev/null", out), 0) << out;
    const auto j = nlohmann::json::parse(out);
    EXPECT_EQ(j.at("tiles_touched"), 1);
    EXPECT_EQ(j.at("tiles_decoded"), 1);
    EXPECT_EQ(j.at("points_read"), 1'012'412u);
    const auto written = j.at("points_written").get<std::uint64_t>();
    EXPECT_GT(written, 100'000u);
    EXPECT_LT(written, 1'012'412u);
    EXPECT_TRUE(j.at("skipped").empty());
    ASSERT_EQ(test::run_command(cli() + "info " + path("west.laz") + " 2>&1", out), 0) << out;
    EXPECT_NE(out.find("EPSG:3089"), std::string::npos) << out;
    EXPECT_NE(out.find(std::to_string(written).insert(std::to_string(written).size() - 3, ",")), std::string::npos)
        << out;
}

TEST_F(ClipCommand, ABowTieIsClippedWithOneWarningNamingItsCrossing) {
    // Over the Woodford tile (US survey feet): crossing at (5208700, 3904000).
    const std::string bow = "POLYGON ((5208400 3903700, 5209000 3904300, 5209000 3903700, 5208400 3904300))";
    std::ofstream(path("bow.geojson")) << R"({"type": "Polygon", "coordinates": [[[5208400, 3903700], )"
                                          R"([5209000, 3904300], [5209000, 3903700], [5208400, 3904300]]]})";
    const std::string rule = " (outer ring edge 1 and outer ring edge 3); a point is inside where the rings enclose it "
                             "an odd number of times (even-odd rule), which may not be the area meant\n";
    for (const std::string& given : {"'" + bow + "'", path("bow.geojson")}) {
        std::string out;
        ASSERT_EQ(test::run_command(cli() + "clip " + woodford() + " --polygon " + given + " -o " + path("bow.laz") +
                                        " 2>&1", out), 0) << out;
        const std::string name = given == path("bow.geojson") ? given : "the --polygon WKT";
        EXPECT_EQ(out.find("lidarscout: warning: " + name +
                           ": the polygon's edges cross at (5208700.000, 3904000.000)" + rule),
                  0u) << out;
        EXPECT_EQ(std::count(out.begin(), out.end(), '\n'), 2) << "the warning and the result line\n" << out;
    }
    std::string out;
    ASSERT_EQ(test::run_command(cli() + "clip " + woodford() + " --polygon 'POLYGON ((5208400 3903700, 5209000 "
                                        "3903700, 5209000 3904300, 5208400 3904300))' -o " + path("sq.laz") + " 2>&1",
                                out), 0) << out;
    EXPECT_EQ(out.find("warning"), std::string::npos) << out;
}

TEST_F(ClipCommand, CorruptChunkIsNamedAndSkipped) {
    const auto tile = test::damaged_tile(dir).string();
    std::string out;
    const int status = test::run_command(cli() + "clip " + tile + " --bounds 0,0,1e8,1e8 -o " + path("c.laz") +
                                             " --json 2>" + path("err.txt"), out);
    EXPECT_EQ(status, 3) << out;
    const auto j = nlohmann::json::parse(out);
    EXPECT_EQ(j.at("points_written"), 1'012'412u - test::kDamagedChunkPoints);
    ASSERT_EQ(j.at("skipped").size(), 1u) << out;
    EXPECT_EQ(j.at("skipped")[0].at("file"), tile);
    const std::string err = read_text(path("err.txt"));
    EXPECT_EQ(std::count(err.begin(), err.end(), '\n'), 1) << err;
    EXPECT_NE(err.find("skipped " + tile + ": at byte "), std::string::npos) << err;
}

TEST_F(ClipCommand, AnOutputNamedLikeAnInputIsRefused) {
    fs::copy_file(woodford(), dir / "tile.laz");
    fs::permissions(dir / "tile.laz", fs::perms::owner_write, fs::perm_options::add);
    const std::string before = read_text(path("tile.laz"));
    std::string out;
    EXPECT_EQ(test::run_command(cli() + "clip " + path("tile.laz") + kWest + " -o " + path("tile.laz") + " 2>&1",
                                out), 1);
    EXPECT_NE(out.find("refusing the output of -o"), std::string::npos) << out;
    EXPECT_EQ(read_text(path("tile.laz")), before);
    EXPECT_EQ(test::run_command(cli() + "profile " + path("tile.laz") + " --line 5205000,3900000,5206000,3901000 -o " +
                                    path("tile.laz") + " 2>&1", out), 1);
    EXPECT_EQ(read_text(path("tile.laz")), before);
}

TEST_F(ClipCommand, Las15AndWavePacketsToLazReadBackWithInfo) {
    const auto formats = test::formats_dir() / "visgl__loaders.gl";
    const std::pair<const char*, const char*> cases[] = {
        {"modules__las__test__data__pdrf9-1.5.las", "LAS 1.5, point format 9 (63 bytes/record), 1,024 points, LAZ"},
        {"modules__las__test__data__pdrf10-1.5.laz", "LAS 1.5, point format 10 (71 bytes/record), 1,024 points, LAZ"},
        {"modules__las__test__data__pdrf5-1.3.laz", "LAS 1.3, point format 5 (67 bytes/record), 1,024 points, LAZ"},
    };
    for (const auto& [name, header] : cases) {
        std::string out;
        ASSERT_EQ(test::run_command(cli() + "clip " + (formats / name).string() +
                                        " --bounds -3e9,-3e9,3e9,3e9 -o " + path("w.laz") + " --json 2>/dev/null",
                                    out), 0) << out;
        EXPECT_EQ(nlohmann::json::parse(out).at("points_written"), 1024);
        ASSERT_EQ(test::run_command(cli() + "info " + path("w.laz") + " 2>&1", out), 0) << out;
        EXPECT_NE(out.find(header), std::string::npos) << out;
        EXPECT_NE(out.find("WAVEPACKET1"), std::string::npos) << out;
        fs::remove(path("w.laz"));
    }
}

TEST_F(ClipCommand, WaveformDataIsRefusedOnOneLineAndForceDropsIt) {
    const std::string input = (test::formats_dir() / "laspy__laspy" / "tests__data__simple1_3.las").string();
    const std::string command = cli() + "clip " + input + " --bounds -1e9,-1e9,1e9,1e9 -o " + path("w.las");
    std::string out;
    ASSERT_EQ(test::run_command(command + " 2>" + path("err.txt"), out), 1) << out;
    std::string err = read_text(path("err.txt"));
    const auto line = err.find("lidarscout: " + input + ": waveform data packets inside the file");
    EXPECT_NE(line, std::string::npos) << err;
    EXPECT_EQ(std::count(err.begin() + static_cast<long>(std::min(line, err.size())), err.end(), '\n'), 1) << err;
    EXPECT_NE(err.find("nothing written (--force"), std::string::npos) << err;
    fs::remove(path("err.txt"));
    EXPECT_TRUE(fs::is_empty(dir)) << fs::directory_iterator(dir)->path();
    ASSERT_EQ(test::run_command(command + " --force 2>" + path("err.txt"), out), 0) << out;
    err = read_text(path("err.txt"));
    EXPECT_NE(err.find("lidarscout: note: waveform data dropped"), std::string::npos) << err;
    EXPECT_TRUE(fs::exists(path("w.las")));
}

TEST_F(ClipCommand, BadOptionsAreOneLineErrors) {
    std::string out;
    const std::string base = cli() + "clip " + woodford() + " -o " + path("x.laz");
    EXPECT_EQ(test::run_command(base + " --polygon 'POLYGON ((0 0, 1 0, 1 1)' 2>&1", out), 1);
    EXPECT_NE(out.find("expected ')'"), std::string::npos) << out;
    EXPECT_EQ(std::count(out.begin(), out.end(), '\n'), 1) << out;
    EXPECT_EQ(test::run_command(base + kWest + " --classes 2,300 2>&1", out), 1);
    EXPECT_NE(out.find("--classes"), std::string::npos) << out;
    EXPECT_EQ(test::run_command(base + " 2>&1", out), 1);
    EXPECT_NE(out.find("either --bounds or --polygon"), std::string::npos) << out;
    EXPECT_EQ(test::run_command(base + " --bounds 0,0,1,1 2>&1", out), 1);
    EXPECT_NE(out.find("no tile touches the region"), std::string::npos) << out;
    EXPECT_FALSE(fs::exists(path("x.laz")));
}

TEST_F(ClipCommand, MixedCrsAreWrittenInTheCrsAsked) {
    // A tile in UTM 32N and one in UTM 33N; the area in UTM 33N around both.
    std::vector<test::FixturePoint> west, east;
    for (int i = 0; i < 10; ++i) {
        west.push_back({500000.5 + 10 * i, 5400000.5 + 5 * i, 100.0 + i});
        east.push_back({500100.5 + 10 * i, 5400000.5 + 5 * i, 200.0 + i});
    }
    std::vector<double> x, y;
    for (const auto& p : east) x.push_back(p.x), y.push_back(p.y);
    std::vector<double> cx = {499900, 500300}, cy = {5399900, 5400200};
    geo::CrsTransform("EPSG:32632", "EPSG:32633").apply(x, y, {});
    geo::CrsTransform("EPSG:32632", "EPSG:32633").apply(cx, cy, {});
    for (std::size_t i = 0; i < east.size(); ++i) east[i].x = x[i], east[i].y = y[i];
    test::write_fixture(path("west.las"), west, 32632);
    test::write_fixture(path("east.las"), east, 32633);
    const std::string bounds = " --bounds " + std::to_string(std::min(cx[0], cx[1])) + "," +
                               std::to_string(std::min(cy[0], cy[1])) + "," + std::to_string(std::max(cx[0], cx[1])) +
                               "," + std::to_string(std::max(cy[0], cy[1]));
    std::string out;
    ASSERT_EQ(test::run_command(cli() + "clip " + path("west.las") + " " + path("east.las") + bounds +
                                    " --crs EPSG:32633 -o " + path("both.laz") + " --json 2>/dev/null", out), 0)
        << out;
    const auto j = nlohmann::json::parse(out);
    EXPECT_EQ(j.at("points_written"), 20u);
    ASSERT_EQ(j.at("notes").size(), 1u) << out;
    EXPECT_NE(j.at("notes")[0].get<std::string>().find("1 of the 2 tiles touched reprojected into EPSG:32633"),
              std::string::npos) << out;
    ASSERT_EQ(test::run_command(cli() + "info " + path("both.laz") + " 2>&1", out), 0) << out;
    EXPECT_NE(out.find("EPSG:32633"), std::string::npos) << out;
}

TEST_F(ClipCommand, ProfileAsCsvLazAndPng) {
    const std::string base = cli() + "profile " + woodford() + " --line 5205500,3900500,5209500,3904000 --width 10 -o ";
    std::string out;
    ASSERT_EQ(test::run_command(base + path("p.csv") + " --json 2>/dev/null", out), 0) << out;
    const auto points = nlohmann::json::parse(out).at("points_written").get<std::uint64_t>();
    EXPECT_GT(points, 1000u);
    const std::string csv = read_text(path("p.csv"));
    EXPECT_EQ(static_cast<std::uint64_t>(std::count(csv.begin(), csv.end(), '\n')), points + 1);
    ASSERT_EQ(test::run_command(base + path("p.laz") + " --json 2>/dev/null", out), 0) << out;
    EXPECT_EQ(nlohmann::json::parse(out).at("points_written").get<std::uint64_t>(), points);
    ASSERT_EQ(test::run_command(base + path("p.png") + " 2>&1", out), 0) << out;
    const auto png = test::read_png(path("p.png"));
    EXPECT_EQ(png.width, 1600);
    EXPECT_GT(png.height, 100);  // true vertical scale: a 5.3 km line over tens of metres of relief, plus axes
    EXPECT_LT(png.height, 600);
    EXPECT_EQ(test::run_command(base + path("p.txt") + " 2>&1", out), 1);
    EXPECT_NE(out.find(".csv"), std::string::npos) << out;
}

TEST_F(ClipCommand, ATileNamedManyTimesIsClippedOnce) {
    std::vector<test::FixturePoint> points;
    for (int i = 0; i < 5028; ++i) points.push_back({500000.5 + i % 100, 5400000.5 + i / 100, 100.0});
    test::write_fixture(path("t.las"), points, 32632);
    fs::create_directories(dir / "sub");
    nlohmann::json features = nlohmann::json::array();
    for (const std::string& href : std::vector<std::string>{"../t.las", path("t.las"), "../sub/../t.las"}) {
        features.push_back({{"type", "Feature"}, {"id", href}, {"properties", nlohmann::json::object()},
                            {"assets", {{"data", {{"href", href}, {"roles", {"data"}}}}}}});
    }
    std::ofstream(dir / "sub" / "cat.json") << nlohmann::json{{"type", "FeatureCollection"}, {"features", features}};
    const std::string inputs = path("t.las") + " " + path("sub/cat.json") + " " + path("t.las");
    std::string out;
    ASSERT_EQ(test::run_command(cli() + "clip " + inputs + " --bounds 499000,5399000,501000,5401000 -o " +
                                    path("c.laz") + " --json 2>" + path("err.txt"), out), 0) << out;
    EXPECT_EQ(nlohmann::json::parse(out).at("points_written"), 5028u);
    const std::string err = read_text(path("err.txt"));
    const std::string warning =
        "warning: 4 inputs name tiles already named, read once: " + path("t.las") + " (5 times)";
    EXPECT_NE(err.find(warning), std::string::npos) << err;
    EXPECT_EQ(err.find("already named"), err.rfind("already named")) << "one warning: " << err;
    ASSERT_EQ(test::run_command(cli() + "scan --json " + inputs + " 2>/dev/null", out), 0) << out;
    const auto scan = nlohmann::json::parse(out);
    EXPECT_EQ(scan.at("points"), 5028u) << out;
    ASSERT_EQ(scan.at("warnings").size(), 1u) << out;
    EXPECT_NE(scan.at("warnings")[0].get<std::string>().find("4 inputs name tiles already named"), std::string::npos);
}

}  // namespace
}  // namespace lidarscout
