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
}

// The hillshade is placed where the DEM is, as gdalinfo reads it: a GeoTIFF with the DEM's CRS and
// geotransform, or a PNG with its world file (.pgw) and .aux.xml (nothing left beside a temporary name).
TEST_F(DemCommand, HillshadeIsGeoreferencedLikeTheDem) {
    std::string out;
    const std::string cmd = std::string(LIDARSCOUT_CLI) + " dem " + ky() + " -o " + path("ky.tif") +
                            " --texel 4 --from overview --hillshade ";
    ASSERT_EQ(test::run_command(cmd + path("shade.tif") + " 2>/dev/null", out), 0);
    ASSERT_EQ(test::run_command(cmd + path("shade.png") + " 2>/dev/null", out), 0);
    const auto dem = test::gdalinfo(path("ky.tif"));
    ASSERT_TRUE(dem.contains("geoTransform"));
    for (const char* name : {"shade.tif", "shade.png"}) {
        SCOPED_TRACE(name);
        const auto shade = test::gdalinfo(path(name));
        ASSERT_TRUE(shade.contains("coordinateSystem")) << "no CRS";
        const std::string wkt = shade.at("coordinateSystem").at("wkt");
        EXPECT_NE(wkt.find("Kentucky Single Zone (ftUS)"), std::string::npos);
        ASSERT_TRUE(shade.contains("geoTransform"));
        for (int i = 0; i < 6; ++i) {
            EXPECT_NEAR(shade.at("geoTransform").at(i).get<double>(), dem.at("geoTransform").at(i).get<double>(), 1e-6);
        }
        EXPECT_EQ(shade.at("size"), dem.at("size"));
    }
    EXPECT_TRUE(fs::exists(path("shade.pgw")));
    EXPECT_TRUE(fs::exists(path("shade.png.aux.xml")));
    const auto png = test::read_png(path("shade.png"));
    EXPECT_GT(png.width, 0);
    std::size_t sidecars = 0;
    for (const auto& e : fs::directory_iterator(dir)) sidecars += e.path().filename().string().find("shade.") == 0;
    EXPECT_EQ(sidecars, 4u);  // shade.tif, shade.png, shade.pgw, shade.png.aux.xml: no temporary leftovers
    EXPECT_EQ(test::run_command(cmd + path("shade.jpg") + " 2>&1", out), 1);
    EXPECT_NE(out.find("must end in .tif (GeoTIFF) or .png"), std::string::npos) << out;
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

}  // namespace
}  // namespace lidarscout
