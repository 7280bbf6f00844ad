// `lidarscout dem`: a Kentucky DEM in the tiles' CRS (US survey feet, as gdalinfo reads it),
// with its orthophoto and hillshade, JSON output; bad options are one-line errors (exit 1); a
// raster over the memory budget is refused before it is allocated, a hostile --threads capped,
// and a corrupt chunk costs only its points (exit 3); --product writes several rasters in one
// read, each to its own checked name; --ground smrf makes the dtm of an unclassified survey; the memory
// estimate bounds the peak; contours are counted before they are drawn.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <iterator>

#include <nlohmann/json.hpp>

#include "child_process.hpp"
#include "core/thread_pool.hpp"
#include "damaged_tile.hpp"
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
    EXPECT_NE(out.find("it must end in one of .tif, .tiff, .png (.jpg given)"), std::string::npos) << out;
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
    EXPECT_EQ(test::run_command(base + " --from overview --returns last 2>&1", out), 1);
    EXPECT_NE(out.find("--returns applies to --from full only"), std::string::npos) << out;
    EXPECT_EQ(test::run_command(base + " --intensity 9-2 2>&1", out), 1);
    EXPECT_NE(out.find("--intensity"), std::string::npos) << out;
    EXPECT_FALSE(fs::exists(path("x.tif")));
}

// --returns and --intensity (PointFilter) leave points out of a full-resolution DEM: the
// Woodford tile's last returns with intensity 10 and more are fewer than all its points.
TEST_F(DemCommand, ReturnsAndIntensityFilterTheFullDem) {
    const std::string base = std::string(LIDARSCOUT_CLI) + " dem " +
                             (test::surveys_dir() / "ky-woodford-county").string() + " --texel 4 --json -o ";
    std::string out;
    ASSERT_EQ(test::run_command(base + path("all.tif") + " 2>/dev/null", out), 0) << out;
    const auto all = nlohmann::json::parse(out);
    ASSERT_EQ(test::run_command(base + path("last.tif") + " --returns last --intensity 10- 2>/dev/null", out), 0)
        << out;
    const auto last = nlohmann::json::parse(out);
    EXPECT_EQ(last.at("points_read"), all.at("points_read"));
    EXPECT_EQ(all.at("points_used"), all.at("points_read"));
    EXPECT_LT(last.at("points_used").get<std::uint64_t>(), all.at("points_used").get<std::uint64_t>());
    EXPECT_GT(last.at("points_used").get<std::uint64_t>(), 0u);
}

std::string woodford() { return (test::surveys_dir() / "ky-woodford-county").string(); }

// No file is left in the output's folder but the ones named.
std::size_t files_in(const fs::path& dir) {
    return static_cast<std::size_t>(std::distance(fs::directory_iterator(dir), fs::directory_iterator()));
}

// --texel 0.001 on a 600 m tile: 565,208 x 611,565 texels (1.4 TB); it was killed at 24 GB.
// --product: several rasters from one read of the points, each to OUT_NAME.tif, each a COG with the
// survey's CRS and nodata as gdalinfo reads it; --json names them; -o itself is not written.
TEST_F(DemCommand, ProductsInOneReadEachToItsFile) {
    std::string out;
    ASSERT_EQ(test::run_command(std::string(LIDARSCOUT_CLI) + " dem " + woodford() + " --texel 4 --json -o " +
                                    path("plain.tif") + " 2>/dev/null", out), 0) << out;
    const auto plain = nlohmann::json::parse(out);
    ASSERT_EQ(test::run_command(std::string(LIDARSCOUT_CLI) + " dem " + woodford() + " --texel 4 --json -o " +
                                    path("w.tif") + " --product dtm,dsm,chm,density --hillshade " + path("w.png") +
                                    " 2>/dev/null", out), 0) << out;
    const auto j = nlohmann::json::parse(out);
    EXPECT_EQ(j.at("points_read"), plain.at("points_read"));
    EXPECT_EQ(j.at("max_edge_m").get<double>(), 80.0);  // 20 texels
    for (const std::string name : {"dtm", "dsm", "chm", "density"}) {
        EXPECT_EQ(j.at("products").at(name), (dir / ("w_" + name + ".tif")).string());
        const auto info = test::gdalinfo((dir / ("w_" + name + ".tif")).string());
        ASSERT_TRUE(info.contains("bands")) << name;
        EXPECT_EQ(info.at("metadata").at("IMAGE_STRUCTURE").at("LAYOUT"), "COG") << name;
        const std::string wkt = info.at("coordinateSystem").at("wkt");
        EXPECT_NE(wkt.find("Kentucky Single Zone (ftUS)"), std::string::npos) << name;
        EXPECT_EQ(info.at("bands").at(0).at("noDataValue").get<double>(), -9999.0) << name;
        EXPECT_EQ(info.at("bands").at(0).contains("unit"), name != "density") << name;
    }
    EXPECT_FALSE(fs::exists(path("w.tif")));
    EXPECT_TRUE(fs::exists(path("w.png")));
}

// Options that do not fit products, an unknown product, a derived name another output takes and a
// hillshade without a height product are refused in one line before anything is written.
TEST_F(DemCommand, ProductOptionsAreCheckedBeforeAnyWork) {
    std::string out;
    const std::string base = std::string(LIDARSCOUT_CLI) + " dem " + woodford() + " --texel 4 -o " + path("x.tif");
    EXPECT_EQ(test::run_command(base + " --product canopy 2>&1", out), 1);
    EXPECT_NE(out.find("unknown product 'canopy'"), std::string::npos) << out;
    EXPECT_EQ(test::run_command(base + " --product dtm --method tin 2>&1", out), 1);
    EXPECT_NE(out.find("--method does not apply to --product"), std::string::npos) << out;
    EXPECT_EQ(test::run_command(base + " --product dsm --returns last 2>&1", out), 1);
    EXPECT_NE(out.find("--returns"), std::string::npos) << out;
    EXPECT_EQ(test::run_command(base + " --product dtm,dsm --hillshade " + path("x_dsm.tif") + " 2>&1", out), 1);
    EXPECT_NE(out.find("it is also the output of"), std::string::npos) << out;
    EXPECT_EQ(std::count(out.begin(), out.end(), '\n'), 1) << out;
    EXPECT_EQ(test::run_command(base + " --product density --hillshade " + path("h.png") + " 2>&1", out), 1);
    EXPECT_NE(out.find("--hillshade needs a dtm, dsm or chm product"), std::string::npos) << out;
    EXPECT_EQ(files_in(dir), 0u);
}

// --ground smrf: an unclassified survey, whose dtm the ground classes cannot make (the error says
// what to give), gets one from the ground filter, reported in the JSON; its options are refused
// where they do not apply, before any work.
TEST_F(DemCommand, AGroundFilterMakesTheDtmOfAnUnclassifiedSurvey) {
    std::string out;
    const std::string base = std::string(LIDARSCOUT_CLI) + " dem " + ky() + " --texel 5 -o " + path("g.tif");
    EXPECT_EQ(test::run_command(base + " --product dtm 2>&1", out), 1);
    EXPECT_NE(out.find("no point of the dtm's classes 2,9 lies in the area (2563625 points read), so the dtm would "
                       "be empty; nothing written: give --classes, or --ground smrf"), std::string::npos) << out;
    EXPECT_EQ(test::run_command(base + " --product dsm --ground smrf 2>&1", out), 1);
    EXPECT_NE(out.find("--ground applies to the dtm and chm products"), std::string::npos) << out;
    EXPECT_EQ(test::run_command(base + " --product dtm --ground-slope 0.3 2>&1", out), 1);
    EXPECT_NE(out.find("--ground-slope applies to --ground smrf"), std::string::npos) << out;
    EXPECT_EQ(test::run_command(base + " --product dtm --ground smrf --ground-window 0 2>&1", out), 1);
    EXPECT_NE(out.find("--ground-window (metres) must be a positive number"), std::string::npos) << out;
    EXPECT_EQ(test::run_command(base + " --product dtm --ground smrf --ground-slope 0 2>&1", out), 1);
    EXPECT_NE(out.find("--ground-slope must be a positive rise over run"), std::string::npos) << out;
    EXPECT_EQ(test::run_command(base + " --product dtm --ground smrf --ground-window 200 2>&1", out), 1);
    EXPECT_NE(out.find("--ground-window 200 m is more than half the 64-texel margin a block sees at --texel 5 (160 m)"),
              std::string::npos) << out;
    EXPECT_EQ(test::run_command(base + " --ground smrf 2>&1", out), 1);
    EXPECT_NE(out.find("--ground applies to --product dtm or chm"), std::string::npos) << out;
    EXPECT_EQ(test::run_command(base + " --product dtm --ground lasground 2>&1", out), 1);
    EXPECT_NE(out.find("--ground must be classes or smrf"), std::string::npos) << out;
    EXPECT_TRUE(fs::is_empty(dir)) << out;

    ASSERT_EQ(test::run_command(base + " --product dtm,dsm,chm --ground smrf --ground-slope 0.3 --json 2>/dev/null",
                                out), 0) << out;
    const auto j = nlohmann::json::parse(out);
    EXPECT_EQ(j["ground"]["filter"], "smrf");
    EXPECT_EQ(j["ground"]["slope"], 0.3);
    EXPECT_EQ(j["ground"]["window_m"], 18.0);
    const auto dtm = test::read_raster(path("g_dtm.tif")), dsm = test::read_raster(path("g_dsm.tif"));
    ASSERT_EQ(dtm.values.size(), dsm.values.size());
    std::size_t both = 0, below = 0;
    for (std::size_t i = 0; i < dtm.values.size(); ++i) {
        if (dtm.values[i] == -9999.0f || dsm.values[i] == -9999.0f) continue;
        ++both;
        below += dtm.values[i] <= dsm.values[i] + 0.01f;
    }
    EXPECT_GT(both, dtm.values.size() * 9 / 10) << "the terrain under nearly every texel";
    EXPECT_GT(below, both * 99 / 100) << "the terrain under the surface";
}

// --contours: GDAL's contour lines of the dtm (the first height product) or of the DEM, every
// INTERVAL feet here, in a GeoPackage beside it with the raster's CRS, as ogrinfo reads it back:
// lines with an elevation that is a multiple of the interval, within the raster's heights.
TEST_F(DemCommand, ContoursOfTheHeightRasterInAGeoPackage) {
    std::string out;
    ASSERT_EQ(test::run_command(std::string(LIDARSCOUT_CLI) + " dem " + woodford() + " --texel 2 --json -o " +
                                    path("c.tif") + " --product density,dtm --contours 5 2>/dev/null", out), 0) << out;
    const auto j = nlohmann::json::parse(out);
    EXPECT_EQ(j.at("contours"), path("c_dtm_contours.gpkg"));
    EXPECT_GT(j.at("contour_lines").get<int>(), 10);
    ASSERT_EQ(test::run_command("ogrinfo -so -al " + path("c_dtm_contours.gpkg") + " 2>&1", out), 0) << out;
    EXPECT_NE(out.find("Geometry: Line String"), std::string::npos) << out;
    EXPECT_NE(out.find("Feature Count: " + std::to_string(j.at("contour_lines").get<int>())), std::string::npos);
    EXPECT_NE(out.find("Kentucky Single Zone (ftUS)"), std::string::npos) << out;
    EXPECT_NE(out.find("elevation: Real"), std::string::npos) << out;
    ASSERT_EQ(test::run_command("ogrinfo -q -sql \"SELECT MIN(elevation) AS lo, MAX(elevation) AS hi, "
                                "SUM(elevation - 5 * CAST(elevation / 5 AS INTEGER)) AS off FROM contours\" " +
                                    path("c_dtm_contours.gpkg") + " 2>&1", out), 0) << out;
    EXPECT_NE(out.find("off (Real) = 0"), std::string::npos) << out;  // every line on a multiple of 5 ft
    const auto dtm = test::read_raster(path("c_dtm.tif"));
    float lo = 1e9f, hi = -1e9f;
    for (const float v : dtm.values) {
        if (v != -9999.0f) lo = std::min(lo, v), hi = std::max(hi, v);
    }
    const auto value = [&](const std::string& name) {
        const auto at = out.find(name + " (Real) = ");
        return at == std::string::npos ? -1e9 : std::stod(out.substr(at + name.size() + 10));
    };
    EXPECT_GE(value("lo"), lo);
    EXPECT_LE(value("hi"), hi);
    // the plain DEM's contours; a product set without a height raster has none to draw
    ASSERT_EQ(test::run_command(std::string(LIDARSCOUT_CLI) + " dem " + woodford() + " --texel 4 -o " + path("m.tif") +
                                    " --contours 10 2>/dev/null", out), 0) << out;
    EXPECT_TRUE(fs::exists(path("m_contours.gpkg")));
    EXPECT_EQ(test::run_command(std::string(LIDARSCOUT_CLI) + " dem " + woodford() + " --texel 4 -o " + path("n.tif") +
                                    " --product count --contours 10 2>&1", out), 1);
    EXPECT_NE(out.find("--contours needs a dtm, dsm or chm product"), std::string::npos) << out;
    EXPECT_FALSE(fs::exists(path("n.tif")));
}

// The contours are counted before GDAL draws them: the count is in the JSON (within a factor of 2 of
// the lines drawn), GDAL says nothing on stderr (its GeoPackage driver once warned about the
// temporary name's extension on every run), and an interval that would draw too many lines is
// refused in one line that names the count, the limit and an interval that fits.
TEST_F(DemCommand, ContoursAreCountedBeforeTheyAreDrawn) {
    std::string out;
    ASSERT_EQ(test::run_command(std::string(LIDARSCOUT_CLI) + " dem " + woodford() + " --texel 4 --json -o " +
                                    path("c.tif") + " --contours 2 2>" + path("err.txt"), out), 0) << out;
    const auto j = nlohmann::json::parse(out);
    const double lines = j.at("contour_lines").get<double>(), counted = j.at("contour_lines_estimate").get<double>();
    EXPECT_GT(lines, 100);
    EXPECT_GE(counted, lines / 2);
    EXPECT_LE(counted, lines * 2);
    EXPECT_GT(j.at("contour_points_estimate").get<double>(), counted);
    std::ifstream err(path("err.txt"));
    const std::string stderr_text{std::istreambuf_iterator<char>(err), std::istreambuf_iterator<char>()};
    EXPECT_EQ(stderr_text.find("Warning"), std::string::npos) << stderr_text;
    EXPECT_EQ(stderr_text.find("extension"), std::string::npos) << stderr_text;
    fs::create_directories(dir / "out");
    const auto run = test::run_measured(std::string(LIDARSCOUT_CLI) + " dem " + woodford() + " --texel 2 -o " +
                                            (dir / "out" / "d.tif").string() + " --contours 0.01",
                                        dir / "err2.txt");
    EXPECT_EQ(run.status, 1) << run.err;
    EXPECT_EQ(std::count(run.err.begin(), run.err.end(), '\n'), 1) << run.err;
    EXPECT_NE(run.err.find("--contours 0.01 would draw about "), std::string::npos) << run.err;
    EXPECT_NE(run.err.find("(limit 200 k lines)"), std::string::npos) << run.err;
    EXPECT_NE(run.err.find("try --contours "), std::string::npos) << run.err;
    EXPECT_NE(run.err.find("or --force to draw them all"), std::string::npos) << run.err;
    EXPECT_FALSE(fs::exists(dir / "out" / "d_contours.gpkg"));
}

TEST_F(DemCommand, HugeRasterIsRefusedBeforeAllocation) {
    fs::create_directories(dir / "out");
    const auto run = test::run_measured(std::string(LIDARSCOUT_CLI) + " dem " + woodford() + " -o " +
                                            (dir / "out" / "d.tif").string() + " --texel 0.001 --threads 100000",
                                        dir / "err.txt");
    EXPECT_EQ(run.status, 1) << run.err;
    EXPECT_NE(run.err.find("565208 x 611565 texels"), std::string::npos) << run.err;
    EXPECT_NE(run.err.find("give a larger --texel (e.g. --texel "), std::string::npos) << run.err;
    EXPECT_LT(run.max_rss_kb, 300 * 1024) << run.err;
    EXPECT_LE(run.max_threads, max_threads() + 32u) << run.err;  // capped (plus the header readers)
    EXPECT_NE(run.err.find("--threads 100000 is more than"), std::string::npos) << run.err;
    EXPECT_EQ(files_in(dir / "out"), 0u);  // no scratch raster left behind
}

// Under a 4 GB address-space limit the budget is 2 GB: --texel 0.05 (about 5 GB at once) is
// refused in one line instead of ending in std::bad_alloc.
TEST_F(DemCommand, MemoryLimitIsTheBudget) {
    fs::create_directories(dir / "out");
    const auto run = test::run_measured("sh -c 'ulimit -v 4000000 && exec " + std::string(LIDARSCOUT_CLI) + " dem " +
                                            woodford() + " -o " + (dir / "out" / "d.tif").string() + " --texel 0.05'",
                                        dir / "err.txt");
    EXPECT_EQ(run.status, 1) << run.err;
    EXPECT_EQ(std::count(run.err.begin(), run.err.end(), '\n'), 1) << run.err;
    EXPECT_NE(run.err.find("over the budget of 2.05 GB"), std::string::npos) << run.err;
    EXPECT_EQ(run.err.find("bad_alloc"), std::string::npos) << run.err;
    EXPECT_EQ(files_in(dir / "out"), 0u);
}

TEST_F(DemCommand, CorruptChunkCostsOnlyItsPoints) {
    const auto tile = test::damaged_tile(dir).string();
    std::string out;
    const int status = test::run_command(std::string(LIDARSCOUT_CLI) + " dem " + tile + " -o " + path("d.tif") +
                                             " --texel 2 --json 2>" + path("err.txt"), out);
    EXPECT_EQ(status, 3) << out;
    EXPECT_TRUE(fs::exists(path("d.tif")));
    const auto j = nlohmann::json::parse(out);
    EXPECT_EQ(j.at("points_skipped"), test::kDamagedChunkPoints);
    EXPECT_EQ(j.at("points_read"), 1'012'412u - test::kDamagedChunkPoints);
    ASSERT_EQ(j.at("skipped_chunks").size(), 1u) << out;
    EXPECT_EQ(j.at("skipped_chunks")[0].at("file"), tile);
    const auto cause = j.at("skipped_chunks")[0].at("cause").get<std::string>();
    EXPECT_NE(cause.find(test::kDamagedChunkText), std::string::npos) << cause;
    std::ifstream in(path("err.txt"));
    const std::string err((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    EXPECT_EQ(std::count(err.begin(), err.end(), '\n'), 1) << err;
    EXPECT_NE(err.find("skipped " + tile + ": at byte "), std::string::npos) << err;
    // The undamaged tile: exit 0.
    EXPECT_EQ(test::run_command(std::string(LIDARSCOUT_CLI) + " dem " + woodford() + " -o " + path("c.tif") +
                                    " --texel 2 2>&1", out), 0) << out;
}

// Two copies of the Woodford tile side by side, the west one's header max x moved to its middle:
// its eastern points land in blocks beyond its header bounds (possibly already written). That
// ended the whole DEM; now those points are left out, named and counted.
TEST_F(DemCommand, PointsBeyondTheirHeaderBoundsCostOnlyThemselves) {
    std::string out;
    ASSERT_EQ(test::run_command(std::string(LIDARSCOUT_CLI) + " synth replicate " + woodford() + " --grid 2x1 -o " +
                                    path("tiles") + " 2>&1", out), 0) << out;
    const fs::path west = dir / "tiles" / "5205000_3900000_x0_y0.laz";
    fs::permissions(west, fs::perms::owner_write, fs::perm_options::add);
    {
        std::fstream f(west, std::ios::in | std::ios::out | std::ios::binary);
        double max_min_x[2];
        f.seekg(179);  // LAS 1.2: max x, min x (scaled units, doubles)
        f.read(reinterpret_cast<char*>(max_min_x), sizeof max_min_x);
        const double middle = 0.5 * (max_min_x[0] + max_min_x[1]);
        f.seekp(179);
        f.write(reinterpret_cast<const char*>(&middle), sizeof middle);
    }
    fs::remove(dir / "tiles" / "replicate.json");
    const int status = test::run_command(std::string(LIDARSCOUT_CLI) + " dem " + path("tiles") + " -o " +
                                             path("d.tif") + " --texel 0.25 --json 2>/dev/null", out);
    EXPECT_EQ(status, 3) << out;
    EXPECT_TRUE(fs::exists(path("d.tif")));
    const auto j = nlohmann::json::parse(out);
    ASSERT_EQ(j.at("skipped_chunks").size(), 1u) << out;
    EXPECT_EQ(j.at("skipped_chunks")[0].at("file"), west.string());
    EXPECT_NE(j.at("skipped_chunks")[0].at("cause").get<std::string>().find("outside the tile's header bounds"),
              std::string::npos) << out;
    EXPECT_GT(j.at("points_skipped").get<std::uint64_t>(), 100'000u);
    EXPECT_EQ(j.at("points_used").get<std::uint64_t>() + j.at("points_skipped").get<std::uint64_t>(),
              2u * 1'012'412u);
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
    EXPECT_NE(out.find("no point of classes 7 lies in the area (2563625 points read); nothing written"),
              std::string::npos) << out;
    EXPECT_TRUE(fs::is_empty(dir)) << "nothing may be left behind";
    EXPECT_EQ(test::run_command(dem + "--classes 0 > /dev/null 2>&1", out), 0);  // the control: its points are class 0
    EXPECT_TRUE(fs::exists(path("x.tif")));
}

// The memory estimate (what --memory is checked against) bounds what the run holds at its peak
// (the whole process, reading included), and not by more than three times (1.7-2.1 measured).
TEST_F(DemCommand, MemoryEstimateBoundsThePeak) {
    for (const char* args : {"--texel 1", "--texel 1 --product dtm,dsm,chm", "--texel 2 --method tin"}) {
        std::string out;
        ASSERT_EQ(test::run_command(std::string(LIDARSCOUT_CLI) + " dem " + woodford() + " " + args + " --json -o " +
                                        path("m.tif") + " 2>/dev/null",
                                    out),
                  0)
            << args;
        const auto j = nlohmann::json::parse(out);
        const auto estimate = j.at("memory_estimate_bytes").get<double>();
        const auto peak = j.at("peak_resident_bytes").get<double>();
        EXPECT_GE(estimate, peak) << args;
        EXPECT_LT(estimate, 3.0 * peak) << args;
    }
}

}  // namespace
}  // namespace lidarscout
