// What `clip`, `profile`, `convert` and `dem` write as a user meets them (issue 53): the output states one
// CRS, the target, read back by `info --json` (its CRS records and the CRS they name); a no-op
// reprojection keeps the vertical CRS; an empty clip, profile or contour set is one error line that
// says why (exit 1) and writes nothing; tiles in degrees are clipped in degrees or reprojected with
// --crs, refused by profile and dem without --crs naming the UTM zone to give; bounds in degrees on
// projected data (and in metres on degrees) get a hint. Counts against brute-force passes over the tiles.
#include <gtest/gtest.h>

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "dataset/dataset.hpp"
#include "geo/crs_definition.hpp"
#include "geo/projection.hpp"
#include "las_fixture.hpp"
#include "temp_dir_fixture.hpp"
#include "test_data.hpp"

namespace lidarscout {
namespace {

namespace fs = std::filesystem;

std::string cli() { return std::string(LIDARSCOUT_CLI) + " "; }
std::string bcts_2() { return (test::surveys_dir() / "lasr-bcts-strips" / "bcts_2.laz").string(); }
std::string autzen_4326() {
    return (test::formats_dir() / "PDAL__PDAL" / "test__data__tindex__autzen_clip_4326.copc.laz").string();
}
// The middle of bcts_2.laz (EPSG:3005+5713: BC Albers, CGVD28 heights), in metres of its CRS.
constexpr std::array<double, 4> kBctsBox = {885050, 629450, 885150, 629600};
// The box, in UTM zone 10N (EPSG:32610).
constexpr std::array<double, 4> kUtmBox = {173036, 5623082, 173241, 5623390};

std::string bounds_option(const std::array<double, 4>& b) {
    return fmt::format(" --bounds {:.7f},{:.7f},{:.7f},{:.7f}", b[0], b[1], b[2], b[3]);
}

// How many points of the one tile `path` lie in box `b` once placed in `crs` (as stored when empty).
std::uint64_t brute_force(const std::string& path, const std::array<double, 4>& b, const std::string& crs = "") {
    dataset::DatasetOptions options;
    options.accept_degrees = true;
    const auto ds = dataset::open_dataset({path}, options);
    const auto points = test::read_points_back(ds);
    std::vector<double> x, y;
    for (const auto& p : points) x.push_back(p[0]), y.push_back(p[1]);
    if (!crs.empty()) geo::CrsTransform(geo::crs_definition(ds.tiles.at(0).tile.crs()), crs).apply(x, y, {});
    std::uint64_t n = 0;
    for (std::size_t i = 0; i < x.size(); ++i) n += x[i] >= b[0] && x[i] <= b[2] && y[i] >= b[1] && y[i] <= b[3];
    return n;
}

// `info --json` of one file: its first (only) tile.
nlohmann::json info(const std::string& path) {
    std::string out;
    EXPECT_EQ(test::run_command(cli() + "info --json " + path + " 2>/dev/null", out), 0) << out;
    return nlohmann::json::parse(out).at(0);
}

// "user_id record_id" of each record of a tile's JSON that states a CRS, VLRs then EVLRs.
std::vector<std::string> crs_records(const nlohmann::json& tile) {
    std::vector<std::string> out;
    for (const char* list : {"vlrs", "evlrs"}) {
        for (const auto& v : tile.at(list)) {
            const std::string user = v.at("user_id");
            const int id = v.at("record_id");
            const bool geotiff = user == "LASF_Projection" && id >= 34735 && id <= 34737;
            if (geotiff || ((user == "LASF_Projection" || user == "liblas") && (id == 2111 || id == 2112))) {
                out.push_back(user + " " + std::to_string(id));
            }
        }
    }
    return out;
}

using Records = std::vector<std::string>;

class ClipCrs : public test::TempDirTest {
protected:
    // Runs `command` (stderr kept apart); its exit status, stdout in `out`, stderr in `err`.
    int run(const std::string& command, std::string& out, std::string& err) {
        const int status = test::run_command(cli() + command + " 2>" + path("stderr.txt"), out);
        err = read_text(path("stderr.txt"));
        fs::remove(path("stderr.txt"));
        return status;
    }
    static std::string read_text(const std::string& p) {
        std::ifstream in(p);
        return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
    }
    // Whether the temporary folder holds nothing (no output, no temporary file left).
    bool nothing_written() const { return fs::is_empty(dir); }
};

TEST_F(ClipCrs, AReprojectedClipStatesTheTargetCrsOnce) {
    std::string out, err;
    ASSERT_EQ(run("clip " + bcts_2() + bounds_option(kUtmBox) + " --crs EPSG:32610 -o " + path("r.las") + " --json",
                  out, err), 0) << err;
    const auto expected = brute_force(bcts_2(), kUtmBox, "EPSG:32610");
    EXPECT_GT(expected, 1000u);
    EXPECT_EQ(nlohmann::json::parse(out).at("points_written"), expected);
    const auto t = info(path("r.las"));
    EXPECT_EQ(crs_records(t), Records{"LASF_Projection 34735"});  // no WKT of the source's BC Albers left
    EXPECT_EQ(t.at("crs").at("epsg"), 32610);
    EXPECT_TRUE(t.at("crs").at("vertical_epsg").is_null());
    EXPECT_EQ(t.at("global_encoding").get<int>() & 0x10, 0);
    EXPECT_TRUE(t.at("crs").at("warnings").empty());
}

TEST_F(ClipCrs, ANoOpReprojectionKeepsTheVerticalCrs) {
    std::string out, err;
    ASSERT_EQ(run("clip " + bcts_2() + bounds_option(kBctsBox) + " --crs EPSG:3005 -o " + path("a.las") + " --json",
                  out, err), 0) << err;
    const auto j = nlohmann::json::parse(out);
    EXPECT_EQ(j.at("points_written"), brute_force(bcts_2(), kBctsBox));
    for (const auto& note : j.at("notes")) EXPECT_EQ(note.get<std::string>().find("reprojected"), std::string::npos);
    const auto t = info(path("a.las"));
    EXPECT_EQ(t.at("crs").at("epsg"), 3005);
    EXPECT_EQ(t.at("crs").at("vertical_epsg"), 5713);
    // The source's keys (and their ASCII citation) kept, liblas's copy of the WKT dropped with a note.
    EXPECT_EQ(crs_records(t), (Records{"LASF_Projection 34735", "LASF_Projection 34737"}));
    EXPECT_NE(err.find("dropped the liblas 2112 VLR"), std::string::npos) << err;
}

TEST_F(ClipCrs, ConvertStatesTheCrsOnceInTheFormItsFormatExpects) {
    std::string out, err;
    ASSERT_EQ(run("convert " + bcts_2() + " " + path("c.las"), out, err), 0) << err;
    EXPECT_EQ(crs_records(info(path("c.las"))), (Records{"LASF_Projection 34735", "LASF_Projection 34737"}));
    ASSERT_EQ(run("convert " + bcts_2() + " " + path("c6.laz") + " --format 6", out, err), 0) << err;
    const auto t = info(path("c6.laz"));
    EXPECT_EQ(crs_records(t), Records{"LASF_Projection 2112"});
    EXPECT_EQ(t.at("crs").at("source"), "wkt");
    EXPECT_EQ(t.at("crs").at("epsg"), 3005);
    EXPECT_EQ(t.at("crs").at("vertical_epsg"), 5713);
    EXPECT_EQ(t.at("global_encoding").get<int>() & 0x10, 0x10);
}

TEST_F(ClipCrs, EmptyResultsAreErrorsThatSayWhyAndWriteNothing) {
    const std::string clip = "clip " + bcts_2() + " -o " + path("e.las");
    std::string out, err;
    EXPECT_EQ(run(clip + bounds_option(kBctsBox) + " --classes 6", out, err), 1);
    const std::string inside = fmt::format("{}", fmt::group_digits(brute_force(bcts_2(), kBctsBox)));
    EXPECT_NE(err.find("clip: no point of classes 6 in the region (" + inside + " points in it); nothing written"),
              std::string::npos) << err;
    EXPECT_EQ(std::count(err.begin(), err.end(), '\n'), 1) << err;
    EXPECT_EQ(run(clip + " --bounds 885100,629450,885100,629600", out, err), 1);
    EXPECT_NE(err.find("--bounds enclose no area"), std::string::npos) << err;
    EXPECT_TRUE(nothing_written());

    const std::string profile = "profile " + bcts_2() + " -o " + path("p.");
    for (const char* ext : {"csv", "png", "laz"}) {
        EXPECT_EQ(run(profile + ext + " --line 0,0,100,100", out, err), 1) << ext;
        EXPECT_NE(err.find("profile: no tile touches the line's corridor"), std::string::npos) << err;
        EXPECT_EQ(run(profile + ext + " --line 885030,629410,885210,629690 --width 5 --classes 6", out, err), 1);
        EXPECT_NE(err.find("profile: no point of classes 6 in the line's corridor ("), std::string::npos) << err;
    }
    EXPECT_TRUE(nothing_written());

    EXPECT_EQ(run("dem " + bcts_2() + " --texel 5 --contours 100000 -o " + path("d.tif"), out, err), 1);
    EXPECT_NE(err.find("no contour line every 100000: the heights range from "), std::string::npos) << err;
    EXPECT_FALSE(fs::exists(path("d_contours.gpkg")));
}

TEST_F(ClipCrs, TilesInDegreesAreClippedInDegreesOrReprojected) {
    const auto t0 = info(autzen_4326());
    const auto lo = t0.at("bounds").at("min"), hi = t0.at("bounds").at("max");
    // The western half of the tile, in degrees.
    const std::array<double, 4> half = {lo[0], lo[1], (lo[0].get<double>() + hi[0].get<double>()) / 2, hi[1]};
    std::string out, err;
    ASSERT_EQ(run("clip " + autzen_4326() + bounds_option(half) + " -o " + path("deg.laz") + " --json", out, err), 0)
        << err;
    const auto in_half = brute_force(autzen_4326(), half);
    EXPECT_GT(in_half, 0u);
    EXPECT_LT(in_half, t0.at("point_count").get<std::uint64_t>());
    EXPECT_EQ(nlohmann::json::parse(out).at("points_written"), in_half);
    const auto d = info(path("deg.laz"));
    EXPECT_EQ(crs_records(d), Records{"LASF_Projection 2112"});  // point format 7: WKT, the source's
    EXPECT_EQ(d.at("crs").at("epsg"), 4326);
    EXPECT_TRUE(d.at("copc").is_null());  // the COPC records are not carried into a file that is no COPC

    std::vector<double> x = {lo[0], hi[0]}, y = {lo[1], hi[1]};
    geo::CrsTransform("EPSG:4326", "EPSG:32610").apply(x, y, {});
    const std::array<double, 4> utm = {x[0] - 5, y[0] - 5, (x[0] + x[1]) / 2, y[1] + 5};
    ASSERT_EQ(run("clip " + autzen_4326() + bounds_option(utm) + " --crs EPSG:32610 -o " + path("utm.laz") +
                  " --json", out, err), 0) << err;
    EXPECT_EQ(nlohmann::json::parse(out).at("points_written"), brute_force(autzen_4326(), utm, "EPSG:32610"));
    const auto u = info(path("utm.laz"));
    EXPECT_EQ(crs_records(u), Records{"LASF_Projection 2112"});
    EXPECT_EQ(u.at("crs").at("epsg"), 32610);

    const std::string line = fmt::format(" --line {:.3f},{:.3f},{:.3f},{:.3f} --width 60", x[0], (y[0] + y[1]) / 2,
                                         x[1], (y[0] + y[1]) / 2);
    EXPECT_EQ(run("profile " + autzen_4326() + line + " --crs EPSG:32610 -o " + path("p.csv"), out, err), 0) << err;
    EXPECT_EQ(run("dem " + autzen_4326() + " --crs EPSG:32610 --texel 5 -o " + path("d.tif"), out, err), 0) << err;
    EXPECT_TRUE(fs::exists(path("d.tif")));
    for (const std::string& command : {"dem " + autzen_4326() + " --texel 5 -o " + path("d2.tif"),
                                      "profile " + autzen_4326() + line + " -o " + path("p2.csv")}) {
        EXPECT_EQ(run(command, out, err), 1) << command;
        EXPECT_NE(err.find("coordinates are in degrees (longitude, latitude); give --crs EPSG:32610 (WGS 84 / UTM "
                           "zone 10N, at the data's centre)"), std::string::npos) << err;
        EXPECT_EQ(err.find("patches"), std::string::npos) << err;
    }
    EXPECT_FALSE(fs::exists(path("d2.tif")));
    EXPECT_FALSE(fs::exists(path("p2.csv")));
}

TEST_F(ClipCrs, BoundsInTheOtherUnitGetAHint) {
    const std::string woodford = (test::surveys_dir() / "ky-woodford-county" / "5205000_3900000.laz").string();
    std::string out, err;
    EXPECT_EQ(run("clip " + woodford + " --bounds -84.75,38.04,-84.70,38.08 -o " + path("w.laz"), out, err), 1);
    EXPECT_NE(err.find("no tile touches the region"), std::string::npos) << err;
    EXPECT_NE(err.find("the region is given in the CRS's units (EPSG:3089"), std::string::npos) << err;
    EXPECT_NE(err.find("), not in degrees"), std::string::npos) << err;
    EXPECT_EQ(run("clip " + autzen_4326() + " --bounds 494000,4878000,494100,4878100 -o " + path("a.laz"), out, err),
              1);
    EXPECT_NE(err.find("the data is in degrees (longitude, latitude): give the region in degrees, or in metres with "
                       "--crs EPSG:32610 (WGS 84 / UTM zone 10N)"), std::string::npos) << err;
    EXPECT_TRUE(nothing_written());
}

}  // namespace
}  // namespace lidarscout
