// DEMs from the overview: exact on a plane (linear interpolation of chunk points), nodata
// outside the chunk points' hull, and no seams at patch borders on a real survey, for the
// linear method and the network.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>

#include "dataset/dataset.hpp"
#include "las_fixture.hpp"
#include "raster/dem.hpp"
#include "raster/gdal_test_util.hpp"
#include "raster/overview_dem.hpp"
#include "temp_dir_fixture.hpp"

namespace lidarscout {
namespace {

namespace fs = std::filesystem;

using OverviewDem = test::TempDirTest;

TEST(SeamWeight, ZeroOnTheBorderOneInside) {
    EXPECT_EQ(raster::seam_weight(0, 30, 64, 8), 0.0f);
    EXPECT_EQ(raster::seam_weight(30, 63, 64, 8), 0.0f);
    EXPECT_EQ(raster::seam_weight(4, 30, 64, 8), 0.5f);
    EXPECT_EQ(raster::seam_weight(8, 8, 64, 8), 1.0f);
    EXPECT_EQ(raster::seam_weight(32, 32, 64, 8), 1.0f);
}

TEST_F(OverviewDem, LinearIsExactOnAPlaneAndEmptyOutsideTheHull) {
    std::vector<test::FixturePoint> points;
    const auto plane = [](double x, double y) { return 100.0 + 0.1 * (x - 500000) + 0.05 * (y - 5400000); };
    for (int j = 0; j <= 300; ++j) {  // rows of 301 points 1 m apart; 7-point chunks: chunk points every 7 m
        for (int i = 0; i <= 300; ++i) {
            const double x = 500000.0 + i, y = 5400000.0 + j;
            points.push_back({x, y, plane(x, y)});
        }
    }
    test::write_fixture(path("plane.laz"), points, 32632, true, 7);
    const auto ds = dataset::open_dataset({path("plane.laz")});
    raster::DemRequest r;
    r.output = path("dem.tif");
    r.texel_m = 2.0;
    r.source = raster::DemSource::Overview;
    r.method = raster::DemMethod::Linear;
    r.threads = 2;
    r.area = raster::Area{499900, 5399900, 500400, 5400400};  // 100 m of margin beyond the points
    const auto result = raster::make_dem(ds, r);
    const auto dem = test::read_raster(r.output);
    ASSERT_EQ(dem.width, result.grid.width);
    std::size_t valid = 0;
    for (int row = 0; row < dem.height; ++row) {
        for (int col = 0; col < dem.width; ++col) {
            const double x = dem.transform[0] + (col + 0.5) * dem.transform[1];
            const double y = dem.transform[3] + (row + 0.5) * dem.transform[5];
            const bool inside = x > 500001 && x < 500293 && y > 5400001 && y < 5400299;  // chunk points reach x = 294
            const bool outside = x < 499999 || x > 500301 || y < 5399999 || y > 5400301;
            const float v = dem.at(row, col);
            if (inside) {
                ASSERT_NEAR(v, plane(x, y), 2e-3) << x << ", " << y;
                ++valid;
            } else if (outside) {
                ASSERT_EQ(v, -9999.0f) << x << ", " << y;
            }
        }
    }
    EXPECT_GT(valid, 20000u);
}

// Mean absolute step between neighbouring columns that straddle a patch border (every 64th)
// against those inside patches; a seam would show as a larger step at the borders.
double border_to_inside_step(const test::ReadRaster& dem, double west_offset_texels) {
    double border = 0, inside = 0;
    std::size_t nb = 0, ni = 0;
    for (int row = 0; row < dem.height; ++row) {
        for (int col = 1; col < dem.width; ++col) {
            const float a = dem.at(row, col - 1), b = dem.at(row, col);
            if (a == -9999.0f || b == -9999.0f) continue;
            const bool at_border = static_cast<long>(col + west_offset_texels) % 64 == 0;
            (at_border ? border : inside) += std::abs(a - b);
            ++(at_border ? nb : ni);
        }
    }
    return nb && ni ? (border / nb) / (inside / ni) : 1e9;
}

TEST_F(OverviewDem, NoSeamsAtPatchBordersOnARealSurvey) {
    const auto ds = dataset::open_dataset({(test::surveys_dir() / "ky-jmo335-eastern-kentucky").string()});
    for (const auto method : {raster::DemMethod::Linear, raster::DemMethod::Cnn}) {
        SCOPED_TRACE(std::string(raster::dem_method_name(method)));
        raster::DemRequest r;
        r.output = path("ky.tif");
        r.texel_m = 5.0;
        r.source = raster::DemSource::Overview;
        r.method = method;
        r.threads = 2;
        const auto result = raster::make_dem(ds, r);
        EXPECT_GT(result.blocks_written, 20u);
        const auto dem = test::read_raster(r.output);
        const double ratio = border_to_inside_step(dem, 0.0);
        EXPECT_LT(ratio, 1.3);
        EXPECT_GT(ratio, 0.5);
    }
}

}  // namespace
}  // namespace lidarscout
