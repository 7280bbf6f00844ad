// The products of `dem --product` on a real classified survey (the Woodford County tile, US survey
// feet), each against a brute-force computation over every point: count, density and pulse density
// equal to counts per texel, intensity the mean, the dsm the highest first return wherever one
// is, the dtm equal to `--method tin` of the ground and water points, the chm the dsm minus the
// dtm clamped at 0, texel for texel; all made in one read of the points, as gdalinfo sees them;
// a product no point goes to is an error; the dtm from the ground filter matches the classified one.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>

#include "core/thread_pool.hpp"
#include "dataset/dataset.hpp"
#include "dataset/point_stream.hpp"
#include "raster/dem.hpp"
#include "raster/gdal_test_util.hpp"
#include "recon/texel_stats.hpp"
#include "temp_dir_fixture.hpp"

namespace lidarscout {
namespace {

// Per texel of a DEM grid (rows from the north, as the file), what the products count.
struct BruteForce {
    std::vector<std::uint32_t> all, first;  // points and first returns but noise
    std::vector<double> intensity_sum;
    std::vector<double> highest_first;      // metres, -inf where none
};

bool noise(std::uint8_t c) { return c == 7 || c == 18; }

BruteForce brute_force(const dataset::Dataset& ds, const raster::DemGrid& g) {
    const std::size_t n = static_cast<std::size_t>(g.width) * g.height;
    BruteForce b{std::vector<std::uint32_t>(n, 0), std::vector<std::uint32_t>(n, 0), std::vector<double>(n, 0),
                 std::vector<double>(n, -std::numeric_limits<double>::infinity())};
    ThreadPool pool(2);
    for (std::uint32_t t = 0; t < ds.tiles.size(); ++t) {
        dataset::for_each_metric_batch(ds, t, pool, [&](std::uint64_t, std::span<const dataset::MetricPoint> points) {
            for (const auto& p : points) {
                if (noise(p.classification)) continue;
                const auto at = recon::locate_texel(g.block_spec(), g.origin_x, g.origin_y, p.x, p.y);
                if (!at) continue;
                const long col = long(at->cell.ix) * g.block + at->col, row = long(at->cell.iy) * g.block + at->row;
                if (col < 0 || row < 0 || col >= g.width || row >= g.height) continue;
                const std::size_t i = static_cast<std::size_t>(g.height - 1 - row) * g.width + col;
                ++b.all[i];
                b.intensity_sum[i] += p.intensity;
                if (p.return_kinds & returns::kFirst) {
                    ++b.first[i];
                    b.highest_first[i] = std::max(b.highest_first[i], p.z);
                }
            }
        });
    }
    return b;
}

class Products : public test::TempDirTest {
protected:
    static std::string woodford() { return (test::surveys_dir() / "ky-woodford-county").string(); }

    raster::DemRequest request(const std::string& name) const {
        raster::DemRequest r;
        r.output = (dir / name).string();
        r.texel_m = 1.0;
        r.threads = 2;
        return r;
    }
};

TEST_F(Products, EveryProductAgainstABruteForceComputation) {
    const auto ds = dataset::open_dataset({woodford()});
    raster::DemRequest r = request("p.tif");
    r.products = raster::products_from_names("dtm,dsm,chm,density,pulse-density,intensity,count");
    const raster::DemResult d = raster::make_dem(ds, r);
    const std::uint64_t total = ds.tiles.front().tile.header.point_count;
    EXPECT_EQ(d.points_read, total);  // one read for all seven
    ASSERT_EQ(d.outputs.size(), 7u);
    EXPECT_EQ(d.outputs[0], path("p_dtm.tif"));
    EXPECT_EQ(d.outputs[4], path("p_pulse-density.tif"));

    const auto dtm = test::read_raster(path("p_dtm.tif")), dsm = test::read_raster(path("p_dsm.tif"));
    const auto chm = test::read_raster(path("p_chm.tif")), density = test::read_raster(path("p_density.tif"));
    const auto pulses = test::read_raster(path("p_pulse-density.tif"));
    const auto intensity = test::read_raster(path("p_intensity.tif")), count = test::read_raster(path("p_count.tif"));
    const std::size_t n = static_cast<std::size_t>(d.grid.width) * d.grid.height;
    for (const auto* raster : {&dtm, &dsm, &chm, &density, &pulses, &intensity, &count}) {
        ASSERT_EQ(raster->values.size(), n);
        EXPECT_EQ(raster->nodata, -9999.0);
        EXPECT_EQ(raster->epsg, 3089);  // Kentucky Single Zone (ftUS), as every dem output
    }

    const BruteForce b = brute_force(ds, d.grid);
    const double f = ds.frame.z_to_metres, area = r.texel_m * r.texel_m;
    std::size_t highest = 0, filled = 0, canopy = 0, ground = 0;
    for (std::size_t i = 0; i < n; ++i) {
        ASSERT_EQ(count.values[i], static_cast<float>(b.all[i])) << i;
        ASSERT_FLOAT_EQ(density.values[i], static_cast<float>(b.all[i] / area)) << i;
        ASSERT_FLOAT_EQ(pulses.values[i], static_cast<float>(b.first[i] / area)) << i;
        if (b.all[i] == 0) {
            ASSERT_EQ(intensity.values[i], -9999.0f) << i;
        } else {
            ASSERT_NEAR(intensity.values[i], b.intensity_sum[i] / b.all[i], 1e-3) << i;
        }
        if (b.first[i] > 0) {
            ASSERT_NEAR(dsm.values[i], b.highest_first[i] / f, 1e-3) << i;  // the highest first return
            ++highest;
        } else if (dsm.values[i] != -9999.0f) {
            ++filled;  // a hole within the maximum edge, by TIN
        }
        // chm = dsm - dtm, clamped at 0, exactly as the files hold them
        if (dsm.values[i] == -9999.0f || dtm.values[i] == -9999.0f) {
            ASSERT_EQ(chm.values[i], -9999.0f) << i;
        } else {
            ASSERT_EQ(chm.values[i], std::max(0.0f, dsm.values[i] - dtm.values[i])) << i;
            canopy += chm.values[i] > 2 / f;
            ++ground;
        }
    }
    EXPECT_GT(highest, n / 2);
    EXPECT_GT(filled, 0u);
    EXPECT_GT(canopy, 0u);
    EXPECT_GT(ground, n / 2);

    // The dtm is `--method tin --classes 2,9` with the same maximum edge, texel for texel.
    raster::DemRequest tin = request("tin.tif");
    tin.method = raster::DemMethod::Tin;
    tin.filter = PointFilter::parse("2,9", "", "");
    tin.tin_max_edge_m = raster::kDefaultProductMaxEdgeTexels * r.texel_m;
    raster::make_dem(ds, tin);
    const auto reference = test::read_raster(path("tin.tif"));
    ASSERT_EQ(reference.values.size(), n);
    EXPECT_EQ(reference.values, dtm.values);
}

// The dtm from the ground the filter finds among every point of the classified tile (its classes
// unread) against the dtm from its ground class: the same terrain within centimetres at the
// median and half a metre at the 99th percentile of the texels both have, and no more nodata.
TEST_F(Products, AGroundFilteredDtmMatchesTheClassifiedOne) {
    const auto ds = dataset::open_dataset({woodford()});
    raster::DemRequest classes = request("classes.tif");
    classes.products = raster::products_from_names("dtm");
    raster::make_dem(ds, classes);
    raster::DemRequest found = request("found.tif");
    found.products = classes.products;
    found.product_options.ground = recon::GroundFilterParams{};
    raster::make_dem(ds, found);
    const auto a = test::read_raster(path("classes.tif")), b = test::read_raster(path("found.tif"));
    ASSERT_EQ(a.values.size(), b.values.size());
    std::vector<double> d;
    std::size_t only_classes = 0;
    for (std::size_t i = 0; i < a.values.size(); ++i) {
        if (a.values[i] == -9999.0f) continue;
        if (b.values[i] == -9999.0f) {
            ++only_classes;
            continue;
        }
        d.push_back(std::abs(double(a.values[i]) - b.values[i]) * ds.frame.z_to_metres);
    }
    ASSERT_GT(d.size(), a.values.size() / 2);
    std::sort(d.begin(), d.end());
    const double median = d[d.size() / 2], p99 = d[d.size() * 99 / 100];
    std::printf("Woodford 1 m dtm, ground filter against ground class: |difference| median %.3f m, 99th "
                "percentile %.3f m over %zu texels; %zu texels only the classified one has\n", median, p99, d.size(),
                only_classes);
    EXPECT_LT(median, 0.05);
    EXPECT_LT(p99, 0.5);
    EXPECT_LT(only_classes, d.size() / 100);
}

// On the steep, forested Red River Gorge tile (unclassified) the slope the filter takes from the
// terrain keeps more of the hillsides and cliffs as ground than PDAL's fixed 0.15, and still
// takes the canopy away: its dtm has fewer nodata texels, and its chm's median height stays
// within a metre of the fixed slope's.
TEST_F(Products, TheGroundFiltersSlopeFromTheTerrainKeepsSteepGround) {
    const auto ds = dataset::open_dataset({(test::surveys_dir() / "ky-red-river-gorge").string()});
    struct Run {
        double valid = 0, chm_median = 0;
    };
    const auto run = [&](const char* name, double slope) {
        raster::DemRequest r = request(name);
        r.texel_m = 2;
        r.products = raster::products_from_names("dtm,chm");
        recon::GroundFilterParams ground;
        ground.slope = slope;
        r.product_options.ground = ground;
        const auto outputs = raster::make_dem(ds, r).outputs;
        const auto dtm = test::read_raster(outputs[0]), chm = test::read_raster(outputs[1]);
        std::vector<float> heights;
        std::size_t valid = 0;
        for (std::size_t i = 0; i < dtm.values.size(); ++i) {
            valid += dtm.values[i] != -9999.0f;
            if (chm.values[i] != -9999.0f) heights.push_back(chm.values[i]);
        }
        std::sort(heights.begin(), heights.end());
        return Run{double(valid) / dtm.values.size(), heights.empty() ? NAN : heights[heights.size() / 2] * 0.3048};
    };
    const Run fixed = run("fixed.tif", 0.15), terrain = run("terrain.tif", 0);
    std::printf("Red River Gorge 2 m dtm: texels with a height %.2f %% at slope 0.15, %.2f %% at the terrain's; chm "
                "median %.2f m and %.2f m\n", 100 * fixed.valid, 100 * terrain.valid, fixed.chm_median,
                terrain.chm_median);
    EXPECT_GT(terrain.valid, fixed.valid + 0.01);
    EXPECT_NEAR(terrain.chm_median, fixed.chm_median, 1.0);
    EXPECT_GT(terrain.chm_median, 5.0) << "a forest";
}

// One product is written to -o itself; a product with no point in the area is an error, and a
// hillshade needs a height product.
TEST_F(Products, OneProductIsTheOutputItself) {
    const auto ds = dataset::open_dataset({woodford()});
    raster::DemRequest r = request("d.tif");
    r.texel_m = 4;
    r.products = {raster::Product::PulseDensity};
    const raster::DemResult d = raster::make_dem(ds, r);
    ASSERT_EQ(d.outputs, std::vector<std::string>{path("d.tif")});
    const auto info = test::gdalinfo(path("d.tif"));
    EXPECT_EQ(info.at("bands").at(0).at("description"), "first returns per square metre");
    EXPECT_EQ(info.at("metadata").at("IMAGE_STRUCTURE").at("LAYOUT"), "COG");
    r.hillshade = path("h.png");
    r.output = path("e.tif");
    EXPECT_THROW(raster::make_dem(ds, r), Error);
    EXPECT_FALSE(std::filesystem::exists(path("e.tif")));
}

// No silent empty product: a dtm (or chm) of classes no point has is an error naming them, and
// none of the products is written.
TEST_F(Products, AProductWithoutPointsIsAnError) {
    const auto ds = dataset::open_dataset({woodford()});
    raster::DemRequest r = request("q.tif");
    r.texel_m = 4;
    r.products = raster::products_from_names("density,chm");
    r.product_options.dtm_classes = PointFilter::parse("200", "", "");
    try {
        raster::make_dem(ds, r);
        ADD_FAILURE() << "an empty chm was written";
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find("no point of the dtm's classes 200 lies in the area"), std::string::npos)
            << e.what();
    }
    EXPECT_TRUE(std::filesystem::is_empty(dir));
}

TEST_F(Products, NamesAndPaths) {
    EXPECT_EQ(raster::products_from_names("chm,count").size(), 2u);
    EXPECT_THROW(raster::products_from_names("dtm,dtm"), Error);
    EXPECT_THROW(raster::products_from_names("dtm,"), Error);
    EXPECT_THROW(raster::products_from_names("canopy"), Error);
    const std::vector<raster::Product> two = {raster::Product::Dtm, raster::Product::Chm};
    EXPECT_EQ(raster::product_paths("/a/b.tif", two), (std::vector<std::string>{"/a/b_dtm.tif", "/a/b_chm.tif"}));
}

}  // namespace
}  // namespace lidarscout
