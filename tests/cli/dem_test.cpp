// `lidarscout dem`: a Kentucky DEM in the tiles' CRS (US survey feet, as gdalinfo reads it),
// with its orthophoto and hillshade, JSON output; bad options are one-line errors (exit 1).
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>

#include "png_test_util.hpp"
#include "raster/gdal_test_util.hpp"
#include "temp_dir_fixture.hpp"
#include "test_data.hpp"

namespace lidarscout {
namespace {

namespace fs = std::filesystem;

class DemCommand : public test::TempDirTest {
protected:
    static std::string ky() { return (test::surveys_dir() / "ky-red-river-gorge").string(); }
};

TEST_F(DemCommand, KentuckyDemOrthophotoAndHillshade) {
    std::string out;
    const std::string cmd = std::string(LIDARSCOUT_CLI) + " dem " + ky() + " -o " + path("ky.tif") +
                            " --texel 2 --rgb " + path("ky_rgb.tif") + " --hillshade " + path("ky.png") +
                            " --json 2>/dev/null";
    ASSERT_EQ(test::run_command(cmd, out), 0);
    const auto j = nlohmann::json::parse(out);
    EXPECT_EQ(j.at("points_read").get<std::uint64_t>(), 2'563'625u);
    EXPECT_EQ(j.at("points_used"), j.at("points_read"));
    EXPECT_EQ(j.at("method"), "mean");
    const auto info = test::gdalinfo(path("ky.tif"));
    ASSERT_TRUE(info.contains("bands"));
    EXPECT_EQ(info.at("metadata").at("IMAGE_STRUCTURE").at("LAYOUT"), "COG");
    const std::string wkt = info.at("coordinateSystem").at("wkt");
    EXPECT_NE(wkt.find("Kentucky Single Zone (ftUS)"), std::string::npos);
    EXPECT_NE(wkt.find("US survey foot"), std::string::npos);
    EXPECT_NEAR(info.at("geoTransform").at(1).get<double>(), 2.0 * 3937.0 / 1200.0, 1e-9);  // 2 m in US feet
    EXPECT_EQ(info.at("bands").at(0).at("unit"), "US survey foot");
    const auto rgb = test::gdalinfo(path("ky_rgb.tif"));
    ASSERT_EQ(rgb.at("bands").size(), 4u);
    EXPECT_EQ(rgb.at("bands").at(3).at("colorInterpretation"), "Alpha");
    const auto png = test::read_png(path("ky.png"));
    EXPECT_EQ(png.width, j.at("width").get<int>());
    EXPECT_FALSE(fs::exists(path("ky.png") + ".aux.xml"));
}

// --crs: the DEM is written in the CRS asked for (UTM 17N, metres), from the overview here.
TEST_F(DemCommand, WrittenInTheCrsAskedFor) {
    std::string out;
    const std::string cmd = std::string(LIDARSCOUT_CLI) + " dem " + ky() + " -o " + path("utm.tif") +
                            " --texel 5 --from overview --crs EPSG:32617 --json 2>/dev/null";
    ASSERT_EQ(test::run_command(cmd, out), 0);
    const auto dem = test::read_raster(path("utm.tif"));
    EXPECT_EQ(dem.epsg, 32617);
    EXPECT_DOUBLE_EQ(dem.transform[1], 5.0);
    EXPECT_GT(dem.transform[0], 200'000.0);
    EXPECT_LT(dem.transform[0], 800'000.0);
    const auto valid = std::count_if(dem.values.begin(), dem.values.end(), [](float v) { return v != -9999.0f; });
    EXPECT_GT(valid, 1000);
    const float top = *std::max_element(dem.values.begin(), dem.values.end());
    EXPECT_GT(top, 150.0f);  // heights now in metres (the Red River Gorge: ~200-400 m)
    EXPECT_LT(top, 600.0f);
}

TEST_F(DemCommand, BadOptionsAreOneLineErrors) {
    std::string out;
    const std::string base = std::string(LIDARSCOUT_CLI) + " dem " + ky() + " -o " + path("x.tif");
    EXPECT_EQ(test::run_command(base + " --from full --method linear 2>&1", out), 1);
    EXPECT_NE(out.find("does not fit --from full"), std::string::npos) << out;
    EXPECT_EQ(test::run_command(base + " --from sideways 2>&1", out), 1);
    EXPECT_EQ(test::run_command(base + " --classes 2,300 2>&1", out), 1);
    EXPECT_EQ(std::count(out.begin(), out.end(), '\n'), 1) << out;
    EXPECT_NE(out.find("class codes 0-255"), std::string::npos) << out;
    EXPECT_EQ(test::run_command(base + " --method mean --radius 3 2>&1", out), 1);
    EXPECT_NE(out.find("--radius applies to --method idw only"), std::string::npos) << out;
    EXPECT_EQ(test::run_command(base + " --method idw --max-edge 3 2>&1", out), 1);
    EXPECT_NE(out.find("--max-edge applies to --method tin only"), std::string::npos) << out;
    EXPECT_FALSE(fs::exists(path("x.tif")));
}

// No silent empty DEM: --bounds that miss the data are refused with the data's bounds in the same
// units (the survey's US feet; degrees get a hint), a class that matches no point names the
// classes; nothing is written either way.
TEST_F(DemCommand, EmptyResultsAreErrorsThatSayWhy) {
    std::string out;
    const std::string dem = std::string(LIDARSCOUT_CLI) + " dem " + ky() + " -o " + path("x.tif") + " --texel 5 ";
    EXPECT_EQ(test::run_command(dem + "--bounds -83.7,37.7,-83.6,37.8 2>&1", out), 1);
    EXPECT_NE(out.find("do not overlap the data, which lies in "), std::string::npos) << out;
    EXPECT_NE(out.find("in the CRS's units: US survey foot); --bounds are not degrees"), std::string::npos) << out;
    EXPECT_EQ(test::run_command(dem + "--classes 7 2>&1", out), 1);
    EXPECT_NE(out.find("no point of the classes 7 lies in the area (2563625 points read); nothing written"),
              std::string::npos) << out;
    EXPECT_TRUE(fs::is_empty(dir)) << "nothing may be left behind";
    EXPECT_EQ(test::run_command(dem + "--classes 0 > /dev/null 2>&1", out), 0);  // the control: its points are class 0
    EXPECT_TRUE(fs::exists(path("x.tif")));
}

}  // namespace
}  // namespace lidarscout
