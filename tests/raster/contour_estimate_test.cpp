// count_contours against what GDAL's contour generator draws (GDALContourGenerateEx, as write_contours
// calls it, into a memory layer): on DEMs of the shared surveys the lines and points counted before
// the work are within a factor of 2 of those drawn (within 15% when this was written); exact on a
// plane; nothing on a raster of nodata; a raster of several blocks joined at its seams; and make_dem
// refusing contours past its line limit with an interval that fits.
#include <gtest/gtest.h>

#include <gdal_alg.h>
#include <gdal_priv.h>
#include <ogrsf_frmts.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <vector>

#include "core/error.hpp"
#include "dataset/dataset.hpp"
#include "raster/contour_estimate.hpp"
#include "raster/contours.hpp"
#include "raster/dem.hpp"
#include "temp_dir_fixture.hpp"
#include "test_data.hpp"

namespace lidarscout {
namespace {

namespace fs = std::filesystem;

struct Drawn {
    double lines = 0, points = 0;
};

// GDAL's contours of band 1 of `raster` every `interval`, counted in a memory layer.
Drawn drawn_by_gdal(const std::string& raster, double interval, double nodata = -9999) {
    GDALAllRegister();
    GDALDataset* in = static_cast<GDALDataset*>(GDALOpen(raster.c_str(), GA_ReadOnly));
    if (!in) return {};
    GDALDataset* mem = GetGDALDriverManager()->GetDriverByName("Memory")->Create("", 0, 0, 0, GDT_Unknown, nullptr);
    OGRLayer* layer = mem->CreateLayer("contours", nullptr, wkbLineString, nullptr);
    OGRFieldDefn id("id", OFTInteger64), elevation("elevation", OFTReal);
    layer->CreateField(&id), layer->CreateField(&elevation);
    char** options = nullptr;
    options = CSLSetNameValue(options, "LEVEL_INTERVAL", CPLSPrintf("%.17g", interval));
    options = CSLSetNameValue(options, "NODATA", CPLSPrintf("%.17g", nodata));
    options = CSLSetNameValue(options, "ID_FIELD", "0");
    options = CSLSetNameValue(options, "ELEV_FIELD", "1");
    GDALContourGenerateEx(in->GetRasterBand(1), OGRLayer::ToHandle(layer), options, nullptr, nullptr);
    CSLDestroy(options);
    Drawn d;
    layer->ResetReading();
    while (OGRFeature* f = layer->GetNextFeature()) {
        d.lines += 1;
        if (const OGRGeometry* g = f->GetGeometryRef(); g && g->getGeometryType() == wkbLineString) {
            d.points += g->toLineString()->getNumPoints();
        }
        OGRFeature::DestroyFeature(f);
    }
    GDALClose(mem);
    GDALClose(in);
    return d;
}

// A float32 GeoTIFF of width x height texels, z(x, y) (rows from the north), nodata -9999.
template <typename Fn>
void write_raster(const std::string& path, int width, int height, Fn z) {
    GDALAllRegister();
    char** options = CSLSetNameValue(nullptr, "TILED", "YES");
    GDALDataset* out =
        GetGDALDriverManager()->GetDriverByName("GTiff")->Create(path.c_str(), width, height, 1, GDT_Float32, options);
    CSLDestroy(options);
    const double transform[6] = {500000, 1, 0, 5400000, 0, -1};
    out->SetGeoTransform(const_cast<double*>(transform));
    out->GetRasterBand(1)->SetNoDataValue(-9999);
    std::vector<float> row(static_cast<std::size_t>(width));
    for (int y = 0; y < height; ++y) {
        for (int x = 0; x < width; ++x) row[x] = z(x, y);
        EXPECT_EQ(out->GetRasterBand(1)->RasterIO(GF_Write, 0, y, width, 1, row.data(), width, 1, GDT_Float32, 0, 0),
                  CE_None);
    }
    GDALClose(out);
}

class ContourEstimate : public test::TempDirTest {
protected:
    // The DEM of `paths` at `texel` metres (the mean of every point, or `products`' first height
    // product), as make_dem writes it.
    std::string dem(const std::vector<std::string>& paths, double texel, const char* name,
                    std::vector<raster::Product> products = {}) const {
        const auto ds = dataset::open_dataset(paths);
        raster::DemRequest r;
        r.output = path(name);
        r.texel_m = texel;
        r.threads = 2;
        r.products = products;
        const auto result = raster::make_dem(ds, r);
        return result.outputs.front();
    }

    // The counts of `raster` every `interval` within a factor of 2 of GDAL's, both ways.
    static void expect_near_gdal(const std::string& raster, double interval) {
        SCOPED_TRACE(raster + " every " + std::to_string(interval));
        const Drawn d = drawn_by_gdal(raster, interval);
        const double intervals[] = {interval};
        const auto c = raster::count_contours(raster, -9999, intervals).front();
        ASSERT_GT(d.lines, 100);
        std::printf("[ contours ] %s every %g: %.0f lines (%.0f counted, %.3f), %.0f points (%.0f, %.3f)\n",
                    fs::path(raster).filename().c_str(), interval, d.lines, c.lines, c.lines / d.lines, d.points,
                    c.vertices, c.vertices / d.points);
        EXPECT_GE(c.lines, d.lines / 2);
        EXPECT_LE(c.lines, d.lines * 2);
        EXPECT_GE(c.vertices, d.points / 2);
        EXPECT_LE(c.vertices, d.points * 2);
    }
};

std::string survey(const char* name) { return (test::surveys_dir() / name).string(); }

TEST_F(ContourEstimate, WithinAFactorOfTwoOfGdalOnTheSurveys) {
    const std::string woodford = survey("ky-woodford-county/5205000_3900000.laz");
    const std::string w1 = dem({woodford}, 1, "w1.tif"), w5 = dem({woodford}, 5, "w5.tif");
    expect_near_gdal(w1, 1);    // a mean DEM: roofs and trees, many small rings (22.7 k lines)
    expect_near_gdal(w1, 0.3);
    expect_near_gdal(w5, 0.05);
    const std::string dtm = dem({woodford}, 2, "wd.tif", {raster::Product::Dtm});
    expect_near_gdal(dtm, 0.5);  // a terrain model: long lines
    expect_near_gdal(dem({survey("ky-jmo335-eastern-kentucky/N118E380.laz")}, 2, "ky.tif"), 10);
    expect_near_gdal(dem({survey("lasr-bcts-strips/bcts_2.laz")}, 2, "bc.tif"), 1);  // a strip: nodata around it
    expect_near_gdal(dem({survey("ign-lidar-hd-1km/test_semis_2023_0292_6833_LA93_IGN69.laz")}, 1, "ign.tif",
                         {raster::Product::Dtm}),
                     0.5);
}

// On a plane every level is one line across the raster: the count is exact, and every point is a
// crossing of a texel edge.
TEST_F(ContourEstimate, APlaneHasOneLinePerLevel) {
    write_raster(path("plane.tif"), 300, 200, [](int x, int y) { return 100.0f + 0.5f * x + 0.3f * y; });
    const double intervals[] = {1, 10};
    const auto c = raster::count_contours(path("plane.tif"), -9999, intervals);
    for (std::size_t k = 0; k < 2; ++k) {
        const Drawn d = drawn_by_gdal(path("plane.tif"), intervals[k]);
        EXPECT_EQ(c[k].lines, d.lines);
        EXPECT_NEAR(c[k].vertices, d.points, d.points * 0.01);
    }
    EXPECT_EQ(c[0].lines, std::floor((100 + 0.5 * 299 + 0.3 * 199) / 1) - 100);  // the levels the plane spans
}

TEST_F(ContourEstimate, NodataAndFlatRastersHaveNone) {
    write_raster(path("none.tif"), 50, 40, [](int, int) { return -9999.0f; });
    write_raster(path("flat.tif"), 50, 40, [](int, int) { return 12.5f; });
    const double intervals[] = {0.001};
    for (const char* name : {"none.tif", "flat.tif"}) {
        const auto c = raster::count_contours(path(name), -9999, intervals).front();
        EXPECT_EQ(c.lines, 0) << name;
        EXPECT_EQ(c.vertices, 0) << name;
    }
    EXPECT_THROW(raster::count_contours(path("missing.tif"), -9999, intervals), Error);
}

// A raster of 3 x 2 blocks of kContourBlock texels: bumps (rings) over a slope (long lines that cross
// the seams), counted block by block, against GDAL and against the count of the whole grid at once.
TEST_F(ContourEstimate, BlocksJoinAtTheirSeams) {
    const int width = 2 * raster::kContourBlock + 300, height = raster::kContourBlock + 200;
    const auto z = [](int x, int y) {
        return static_cast<float>(0.05 * x + 0.03 * y + 3 * std::sin(x * 0.05) * std::cos(y * 0.07));
    };
    write_raster(path("big.tif"), width, height, z);
    std::vector<float> whole(static_cast<std::size_t>(width) * height);
    for (int y = 0; y < height; ++y) {
        for (int x = 0; x < width; ++x) whole[static_cast<std::size_t>(y) * width + x] = z(x, y);
    }
    const double intervals[] = {2};
    const auto at_once = raster::count_contours(whole.data(), width, height, width, -9999, intervals).front();
    const auto blocks = raster::count_contours(path("big.tif"), -9999, intervals).front();
    EXPECT_DOUBLE_EQ(blocks.vertices - blocks.lines, at_once.vertices - at_once.lines);  // every crossing, once
    EXPECT_GE(blocks.lines, at_once.lines);  // a line across a seam counts a little more than once
    EXPECT_LE(blocks.lines, at_once.lines * 1.5);
    expect_near_gdal(path("big.tif"), 2);
}

TEST(ContourIntervals, RoundIntervalsAboveTheOneAsked) {
    EXPECT_EQ(raster::contour_intervals(0.01, 4), (std::vector<double>{0.01, 0.02, 0.05, 0.1, 0.2}));
    const auto from = raster::contour_intervals(0.03, 3);
    ASSERT_EQ(from.size(), 4u);
    EXPECT_DOUBLE_EQ(from[1], 0.05);
    EXPECT_DOUBLE_EQ(from[2], 0.1);
    EXPECT_DOUBLE_EQ(from[3], 0.2);
    EXPECT_EQ(raster::contour_intervals(250, 2), (std::vector<double>{250, 500, 1000}));
}

// make_dem counts the contours before GDAL draws them: past the limit it refuses, naming the count
// and an interval under the limit, and draws nothing; without a limit (--force) it draws them, as
// many as it counted within a factor of 2; the memory estimate covers them.
TEST_F(ContourEstimate, DemRefusesContoursPastItsLimit) {
    const auto ds = dataset::open_dataset({survey("ky-woodford-county/5205000_3900000.laz")});
    raster::DemRequest r;
    r.output = path("d.tif");
    r.texel_m = 4;
    r.threads = 2;
    r.contours_interval = 1;
    r.contour_line_limit = 500;
    try {
        raster::make_dem(ds, r);
        ADD_FAILURE() << "not refused";
    } catch (const Error& e) {
        const std::string what = e.what();
        EXPECT_NE(what.find("--contours 1 would draw about "), std::string::npos) << what;
        EXPECT_NE(what.find("(limit 500 lines)"), std::string::npos) << what;
        EXPECT_NE(what.find("try --contours 5 (about "), std::string::npos) << what;
        EXPECT_NE(what.find("or --force to draw them all"), std::string::npos) << what;
    }
    EXPECT_FALSE(fs::exists(path("d_contours.gpkg")));
    r.contour_line_limit = 0;
    const raster::DemResult drawn = raster::make_dem(ds, r);
    EXPECT_GT(drawn.contour_lines, 500u);
    EXPECT_GE(drawn.contour_lines_estimate, drawn.contour_lines / 2.0);
    EXPECT_LE(drawn.contour_lines_estimate, drawn.contour_lines * 2.0);
    EXPECT_GE(drawn.memory_estimate, raster::contour_memory_bytes({1, drawn.contour_lines_estimate,
                                                                   drawn.contour_points_estimate},
                                                                  double(drawn.grid.width) * drawn.grid.height));
}

}  // namespace
}  // namespace lidarscout
