// DEMs from every point: a small golden DEM (mean, min, max, a class filter, nodata and the
// geotransform, read back with GDAL), the gdalinfo view of the COG (CRS, nodata, overviews,
// COG layout), mean / idw / tin against gdal_grid's average / invdist / linear, no seams at
// block borders, and `mean` equal texel by texel to the ground truth `eval` scores against.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>

#include "core/error.hpp"
#include "core/thread_pool.hpp"
#include "dataset/dataset.hpp"
#include "las_fixture.hpp"
#include "pipelines/survey_samples.hpp"
#include "raster/dem.hpp"
#include "raster/full_dem.hpp"
#include "raster/gdal_test_util.hpp"
#include "temp_dir_fixture.hpp"

namespace lidarscout {
namespace {

namespace fs = std::filesystem;

class FullDem : public test::TempDirTest {
protected:

    // Four points on a 3 x 3 m grid at (500000, 5400000), UTM 32N: texel (0,0) holds z 10 and
    // 12, texel (1,0) a class-5 point at 20, texel (2,2) one at 30; the rest is empty.
    dataset::Dataset golden() {
        test::write_fixture(path("golden.las"), {{500000.25, 5400000.25, 10, 2, 10, 20, 30},
                                                 {500000.75, 5400000.5, 12, 2, 30, 40, 50},
                                                 {500001.5, 5400000.5, 20, 5, 255, 0, 0},
                                                 {500002.9, 5400002.9, 30, 2, 0, 0, 255}},
                            32632);
        return dataset::open_dataset({path("golden.las")});
    }

    raster::DemRequest request(raster::DemMethod method) const {
        raster::DemRequest r;
        r.output = path("dem.tif");
        r.texel_m = 1.0;
        r.method = method;
        r.threads = 2;
        return r;
    }

    // Points scattered around the texel centres of a 40 x 30 m area (0 to 4 per texel, some texels
    // empty) on a tilted, curved surface, as a LAS tile and as the CSV + VRT that gdal_grid reads.
    // The CSV is relative to the area's corner (500000, 5400000): gdal_grid's Delaunay (qhull)
    // loses the centimetres at UTM coordinates, and its triangles are then not Delaunay.
    dataset::Dataset scattered_points() {
        std::vector<test::FixturePoint> points;
        for (int j = 0; j < 30; ++j) {
            for (int i = 0; i < 40; ++i) {
                const int n = (i * 7 + j * 3) % 5;
                for (int k = 0; k < n; ++k) {
                    const double a = 1.3 * k + 0.1 * i, r = 0.1 + 0.05 * k;
                    points.push_back({500000.5 + i + r * std::cos(a), 5400000.5 + j + r * std::sin(a),
                                      200.0 + 0.37 * i - 0.21 * j + 0.013 * k * k + 0.002 * i * j});
                }
            }
        }
        test::write_fixture(path("points.las"), points, 32632);
        auto ds = dataset::open_dataset({path("points.las")});
        std::FILE* csv = std::fopen(path("points.csv").c_str(), "w");
        std::fprintf(csv, "x,y,z\n");
        for (const auto& p : test::read_points_back(ds)) {
        std::fprintf(csv, "%.4f,%.4f,%.4f\n", p[0] - 500000, p[1] - 5400000, p[2]);
    }
        std::fclose(csv);
        std::ofstream vrt(path("points.vrt"));
        vrt << "<OGRVRTDataSource><OGRVRTLayer name=\"points\"><SrcDataSource>" << path("points.csv")
            << "</SrcDataSource><GeometryType>wkbPoint25D</GeometryType><GeometryField encoding=\"PointFromColumns\" "
               "x=\"x\" y=\"y\" z=\"z\"/></OGRVRTLayer></OGRVRTDataSource>\n";
        return ds;
    }

    // gdal_grid (gdal-bin) with `algorithm` over the scattered points' 40 x 30 texels into grid.tif.
    void gdal_grid(const std::string& algorithm) {
        std::string out;
        ASSERT_EQ(test::run_command("gdal_grid -q -a " + algorithm + " -txe 0 40 -tye 30 0 "
                                    "-outsize 40 30 -ot Float32 -l points " + path("points.vrt") + " " +
                                    path("grid.tif") + " 2>&1", out),
                  0)
            << out;
    }

    // Our DEM and gdal_grid's agree within `tolerance` texel by texel; returns the texels with a value.
    std::size_t compare_with_gdal_grid(float tolerance) {
        const auto ours = test::read_raster(path("dem.tif")), theirs = test::read_raster(path("grid.tif"));
        EXPECT_EQ(theirs.values.size(), ours.values.size());
        std::size_t with_value = 0;
        for (std::size_t i = 0; i < std::min(ours.values.size(), theirs.values.size()); ++i) {
            EXPECT_NEAR(ours.values[i], theirs.values[i], tolerance) << "texel " << i % 40 << ", " << i / 40;
            with_value += ours.values[i] != -9999.0f;
        }
        return with_value;
    }
};

TEST_F(FullDem, GoldenMeanMinMaxAndClasses) {
    const auto ds = golden();
    ASSERT_EQ(ds.tiles.size(), 1u);
    const float nd = -9999.0f;
    struct Case {
        raster::DemMethod method;
        std::vector<int> classes;
        float t00, t10, t22;
    };
    for (const Case& c :
         {Case{raster::DemMethod::Mean, {}, 11, 20, 30}, Case{raster::DemMethod::Min, {}, 10, 20, 30},
          Case{raster::DemMethod::Max, {}, 12, 20, 30}, Case{raster::DemMethod::Mean, {2}, 11, nd, 30}}) {
        SCOPED_TRACE(std::string(raster::dem_method_name(c.method)) + " classes " + std::to_string(c.classes.size()));
        auto r = request(c.method);
        for (const int k : c.classes) r.filter = PointFilter::parse(std::to_string(k), "", "");
        const auto result = raster::make_dem(ds, r);
        EXPECT_EQ(result.grid.width, 3);
        EXPECT_EQ(result.grid.height, 3);
        const auto dem = test::read_raster(r.output);
        ASSERT_EQ(dem.width, 3);
        ASSERT_EQ(dem.height, 3);
        EXPECT_EQ(dem.epsg, 32632);
        ASSERT_TRUE(dem.nodata.has_value());
        EXPECT_EQ(*dem.nodata, -9999.0);
        const double expected_transform[6] = {500000, 1, 0, 5400003, 0, -1};
        for (int i = 0; i < 6; ++i) EXPECT_DOUBLE_EQ(dem.transform[i], expected_transform[i]) << i;
        // rows from the north: texel row j (from the south) is raster row 2 - j
        const std::vector<float> expected = {nd, nd, c.t22, nd, nd, nd, c.t00, c.t10, nd};
        EXPECT_EQ(dem.values, expected);
    }
}

TEST_F(FullDem, OrthophotoIsTheMeanColourWithAlpha) {
    const auto ds = golden();
    auto r = request(raster::DemMethod::Mean);
    r.rgb = path("rgb.tif");
    raster::make_dem(ds, r);
    const auto red = test::read_raster(r.rgb, 1), green = test::read_raster(r.rgb, 2),
               alpha = test::read_raster(r.rgb, 4);
    ASSERT_EQ(red.bands, 4);
    EXPECT_EQ(red.at(2, 0), 20.0f);    // (10 + 30) / 2
    EXPECT_EQ(green.at(2, 0), 30.0f);  // (20 + 40) / 2
    EXPECT_EQ(red.at(2, 1), 255.0f);
    EXPECT_EQ(alpha.at(2, 0), 255.0f);
    EXPECT_EQ(alpha.at(1, 1), 0.0f);  // no point
}

// gdalinfo (gdal-bin) sees a COG: tiled 512 x 512 with overviews, compressed, its CRS, nodata.
TEST_F(FullDem, GdalinfoSeesACloudOptimizedGeoTiff) {
    std::vector<test::FixturePoint> points;
    for (int i = 0; i < 1200; ++i) {  // a diagonal ramp 120 m long at 0.1 m texels: 1200 x 1200
        points.push_back({500000.0 + i * 0.1, 5400000.0 + i * 0.1, 100.0 + i * 0.01});
    }
    test::write_fixture(path("ramp.las"), points, 32632);
    const auto ds = dataset::open_dataset({path("ramp.las")});
    auto r = request(raster::DemMethod::Mean);
    r.texel_m = 0.1;
    raster::make_dem(ds, r);
    const auto info = test::gdalinfo(r.output);
    ASSERT_TRUE(info.contains("bands")) << "gdalinfo failed";
    EXPECT_EQ(info.at("metadata").at("IMAGE_STRUCTURE").at("LAYOUT"), "COG");
    EXPECT_EQ(info.at("metadata").at("IMAGE_STRUCTURE").at("COMPRESSION"), "DEFLATE");
    EXPECT_EQ(info.at("size"), nlohmann::json({1200, 1200}));
    const auto& band = info.at("bands").at(0);
    EXPECT_EQ(band.at("type"), "Float32");
    EXPECT_EQ(band.at("block"), nlohmann::json({512, 512}));
    EXPECT_EQ(band.at("noDataValue"), -9999.0);
    EXPECT_EQ(band.at("unit"), "metre");
    EXPECT_GE(band.at("overviews").size(), 1u);
    EXPECT_NE(info.at("coordinateSystem").at("wkt").get<std::string>().find("WGS 84 / UTM zone 32N"),
              std::string::npos);
    const auto gt = info.at("geoTransform");
    EXPECT_NEAR(gt.at(0).get<double>(), 500000.0, 1e-9);
    EXPECT_NEAR(gt.at(1).get<double>(), 0.1, 1e-12);
    EXPECT_NEAR(gt.at(5).get<double>(), -0.1, 1e-12);
    for (const auto& e : fs::directory_iterator(dir)) {  // no scratch or temporary file left
        EXPECT_EQ(e.path().filename().string().rfind('.', 0), std::string::npos) << e.path();
    }
}

// GDAL's own gridding (gdal_grid -a average) of the same points gives the same values within
// float rounding where every point lies within the circle inscribed in its texel (gdal_grid
// searches a circle around the texel centre, we bin squares).
TEST_F(FullDem, MeanEqualsGdalGridAverage) {
    const auto ds = scattered_points();
    const auto result = raster::make_dem(ds, request(raster::DemMethod::Mean));
    ASSERT_EQ(result.grid.width, 40);
    ASSERT_EQ(result.grid.height, 30);
    gdal_grid("average:radius1=0.5:radius2=0.5:min_points=1:nodata=-9999");
    EXPECT_GT(compare_with_gdal_grid(2e-5f), 800u);
}

// --method idw is gdal_grid's inverse distance to a power within the same radius.
TEST_F(FullDem, IdwEqualsGdalGridInvdist) {
    const auto ds = scattered_points();
    for (const double power : {2.0, 1.5}) {
        SCOPED_TRACE(power);
        auto r = request(raster::DemMethod::Idw);
        r.idw_radius_m = 1.2;
        r.idw_power = power;
        raster::make_dem(ds, r);
        gdal_grid("invdist:power=" + std::to_string(power) +
                             ":smoothing=0:radius1=1.2:radius2=1.2:min_points=1:nodata=-9999");
        EXPECT_GT(compare_with_gdal_grid(2e-4f), 1000u);
    }
}

// --method tin is gdal_grid's linear interpolation in the Delaunay triangulation (nodata outside
// the hull).
TEST_F(FullDem, TinEqualsGdalGridLinear) {
    const auto ds = scattered_points();
    raster::make_dem(ds, request(raster::DemMethod::Tin));
    gdal_grid("linear:radius=0:nodata=-9999");
    EXPECT_GT(compare_with_gdal_grid(2e-4f), 1000u);
}

// Blocks meet without seams: on a real survey, a DEM of a part whose blocks start elsewhere
// (the area shifted by 100.5 texels) has the same value in every texel it shares with the
// whole DEM: exactly for idw, within float rounding for tin (each block interpolates heights
// relative to its own points' median).
TEST_F(FullDem, IdwAndTinHaveNoSeamsAtBlockBorders) {
    const auto site = test::surveys_dir() / "isprs-filter-test-sites" / "CSite1_red1-utm.laz";
    const auto ds = dataset::open_dataset({site.string()});
    ASSERT_EQ(ds.tiles.size(), 1u);
    const auto& b = ds.tiles[0].bounds_m;
    const double texel = 1.0;  // 1,101 x 1,042 texels: 3 x 3 blocks for both methods
    for (const auto method : {raster::DemMethod::Idw, raster::DemMethod::Tin}) {
        SCOPED_TRACE(std::string(raster::dem_method_name(method)));
        auto whole = request(method);
        whole.texel_m = texel;
        whole.tin_max_edge_m = 20;
        const auto w = raster::make_dem(ds, whole);
        ASSERT_GT(w.grid.blocks_x() * w.grid.blocks_y(), 2);
        auto part = whole;
        part.output = path("part.tif");
        part.area = raster::Area{w.grid.origin_x + 100.5 * texel, w.grid.origin_y + 100.5 * texel, b.max_x, b.max_y};
        const auto p = raster::make_dem(ds, part);
        const auto a = test::read_raster(whole.output), c = test::read_raster(part.output);
        const int dx = static_cast<int>(std::lround((p.grid.origin_x - w.grid.origin_x) / texel));
        const int dy = static_cast<int>(std::lround((p.grid.origin_y - w.grid.origin_y) / texel));
        const int top = a.height - (dy + c.height);
        ASSERT_GE(dx, 100);
        std::size_t same = 0;
        for (int row = 0; row < c.height; ++row) {
            for (int col = 0; col < c.width && col + dx < a.width; ++col) {
                const float tolerance = method == raster::DemMethod::Idw ? 0.0f : 2e-4f;
                ASSERT_NEAR(c.at(row, col), a.at(row + top, col + dx), tolerance) << "texel " << col << ", " << row;
                same += c.at(row, col) != -9999.0f;
            }
        }
        EXPECT_GT(same, 50000u);
    }
}

// A tin DEM holds the points of a band of blocks, not of the whole dataset: tiles are read south
// to north and a block is finished when the last tile that reaches it is done. Twelve 100 m tiles
// (2 x 6) of 1 point per m2 under blocks of 64 m: the points held at once (counted before each
// tile's blocks finish) stay within the estimate the memory check uses, and the estimate is a band,
// well under the whole dataset, and not far above what was held.
TEST_F(FullDem, TinBlocksHoldABandOfPointsAsEstimated) {
    std::vector<std::string> files;
    std::uint64_t total = 0;
    for (int ty = 0; ty < 6; ++ty) {
        for (int tx = 0; tx < 2; ++tx) {
            std::vector<test::FixturePoint> points;
            for (int i = 0; i < 10000; ++i) {
                const double u = std::fmod(i * 0.6180339887, 1.0), v = (i + 0.5) / 10000.0;
                points.push_back({500000.0 + 100 * tx + 99.9 * u, 5400000.0 + 100 * ty + 99.9 * v, 200.0 + u + v});
            }
            const std::string name = "t" + std::to_string(tx) + "_" + std::to_string(ty) + ".las";
            files.push_back(path(name.c_str()));
            test::write_fixture(files.back(), points, 32632);
            total += points.size();
        }
    }
    const auto ds = dataset::open_dataset(files);
    ASSERT_EQ(ds.tiles.size(), 12u);
    raster::GridLayer layer;
    layer.gridder.method = raster::GridMethod::Tin;
    layer.gridder.tin_max_edge_m = 5;
    const raster::DemGrid grid = raster::make_dem_grid(raster::dataset_area(ds), 1.0, 64);
    ASSERT_GE(grid.blocks_y(), 9);
    ThreadPool pool(2);
    const auto stats = raster::grid_full_layers(ds, grid, std::span<const raster::GridLayer>(&layer, 1),
                                                [](CellKey, std::vector<raster::BlockImages>&) {}, pool);
    EXPECT_EQ(stats.points_used, total);
    const double estimate = raster::held_points_estimate(ds, grid, std::span<const raster::GridLayer>(&layer, 1));
    const double held = static_cast<double>(stats.peak_held_points);
    EXPECT_GT(held, 0.2 * double(total));
    EXPECT_GE(estimate, held);
    EXPECT_LT(estimate, 2.0 * held);
    EXPECT_LT(estimate, 0.75 * double(total));
}

// Two small tiles 2,100 km apart would make a 2,100,000 x 1,000 texel raster that is nearly all
// nodata: refused at once with a way out, before any point is read.
TEST_F(FullDem, AHugeNearlyEmptyRasterIsRefused) {
    test::write_fixture(path("west.las"), {{500000.5, 5400000.5, 10}, {500010.5, 5400010.5, 11}}, 32632);
    test::write_fixture(path("east.las"), {{2600000.5, 5400000.5, 10}, {2600010.5, 5400999.5, 11}}, 32632);
    const auto ds = dataset::open_dataset({path("west.las"), path("east.las")});
    ASSERT_EQ(ds.tiles.size(), 2u);
    try {
        raster::make_dem(ds, request(raster::DemMethod::Mean));
        FAIL() << "a nearly empty 2 G-texel raster was accepted";
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find("give --bounds, or a larger --texel"), std::string::npos) << e.what();
    }
    auto r = request(raster::DemMethod::Mean);
    r.area = raster::Area{500000, 5400000, 500020, 5400020};  // one of them: fine
    EXPECT_EQ(raster::make_dem(ds, r).points_used, 2u);
    EXPECT_FALSE(fs::exists(path("dem.tif.tmp")));
}

// --from full --method mean is the ground truth of eval (recon::GroundTruth fed by
// pipelines::sample_survey), texel by texel, on a real survey in metres.
TEST_F(FullDem, MeanEqualsEvalGroundTruth) {
    const auto ds =
        dataset::open_dataset({(test::surveys_dir() / "isprs-filter-test-sites" / "CSite1_red1-utm.laz").string()});
    ASSERT_EQ(ds.tiles.size(), 1u);
    const recon::PatchSpec spec{1.0, 64, 16};
    const auto lattice = pipelines::lattice_for(ds, spec);
    const auto cells = pipelines::candidate_patches(ds, lattice, 100000, 1);
    ThreadPool pool(2);
    const auto samples = pipelines::sample_survey(ds, {{lattice, 1u << 30, cells}}, pool);
    const auto& truth = *samples.samples.at(0).truth;

    const auto result = raster::make_dem(ds, request(raster::DemMethod::Mean));
    const auto dem = test::read_raster(path("dem.tif"));
    ASSERT_EQ(dem.width, result.grid.width);
    std::size_t compared = 0, empty = 0;
    for (std::size_t i = 0; i < cells.size(); ++i) {
        const auto h = truth.height_m(i);
        for (int row = 0; row < 64; ++row) {
            for (int col = 0; col < 64; ++col) {
                const double x = lattice.origin_x + (cells[i].ix * 64 + col) * 1.0 - result.grid.origin_x;
                const double y = lattice.origin_y + (cells[i].iy * 64 + row) * 1.0 - result.grid.origin_y;
                const int gc = static_cast<int>(x), gr = dem.height - 1 - static_cast<int>(y);
                if (gc < 0 || gr < 0 || gc >= dem.width || gr >= dem.height) {
                    ASSERT_TRUE(std::isnan(h.at(row, col)));  // outside the DEM: no point there
                    continue;
                }
                const float v = dem.at(gr, gc), t = h.at(row, col);
                if (std::isnan(t)) {
                    EXPECT_EQ(v, -9999.0f);
                    ++empty;
                } else {
                    ASSERT_EQ(v, t) << "texel " << gc << ", " << gr;
                    ++compared;
                }
            }
        }
    }
    EXPECT_GT(compared, 10000u);
    EXPECT_GT(empty, 1000u);
}

}  // namespace
}  // namespace lidarscout
