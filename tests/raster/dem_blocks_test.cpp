// `dem --block I/N` on real surveys: the N pieces cover the grid's blocks once, cut by the points
// the tile headers hold; each piece is a raster on the whole grid's lattice; and the pieces,
// mosaicked by their geotransforms, equal one whole run texel for texel (the decoded float32
// values compared byte for byte, nodata included): the products of the 9 unclassified tiles of
// ky-jmo335 (the dsm's TIN crossing pieces and tiles) and its dtm and chm by the ground filter, the
// dtm and chm of the classified Woodford tile, and the --from full methods there. What a piece
// cannot make (a hillshade, contours, --from overview) is refused.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <set>

#include "dataset/dataset.hpp"
#include "raster/dem.hpp"
#include "raster/dem_blocks.hpp"
#include "raster/gdal_test_util.hpp"
#include "temp_dir_fixture.hpp"

namespace lidarscout {
namespace {

std::string survey(const char* name) { return (test::surveys_dir() / name).string(); }

class DemBlocks : public test::TempDirTest {
protected:
    raster::DemRequest request(const std::string& name, double texel) const {
        raster::DemRequest r;
        r.output = (dir / name).string();
        r.texel_m = texel;
        r.threads = 2;
        return r;
    }

    // Makes the N pieces of `r` (to PIECE_i.tif) and checks that they tile the whole run's raster
    // `whole` exactly, for each of its outputs.
    void expect_pieces_equal_whole(const dataset::Dataset& ds, raster::DemRequest r, const raster::DemResult& whole,
                                   int count) {
        std::vector<std::vector<std::string>> pieces;  // per piece, its outputs
        for (int i = 1; i <= count; ++i) {
            r.output = path(("piece_" + std::to_string(i) + ".tif").c_str());
            r.block_index = i;
            r.block_count = count;
            pieces.push_back(raster::make_dem(ds, r).outputs);
        }
        for (std::size_t o = 0; o < whole.outputs.size(); ++o) {
            const test::ReadRaster all = test::read_raster(whole.outputs[o]);
            ASSERT_FALSE(all.values.empty()) << whole.outputs[o];
            std::vector<int> covered(all.values.size(), 0);
            for (const auto& outputs : pieces) expect_piece_in(all, outputs[o], covered);
            for (std::size_t i = 0; i < covered.size(); ++i) ASSERT_EQ(covered[i], 1) << whole.outputs[o] << " " << i;
        }
    }

    // The piece's texels equal the whole raster's at the piece's place, byte for byte.
    static void expect_piece_in(const test::ReadRaster& all, const std::string& piece_path, std::vector<int>& covered) {
        const test::ReadRaster piece = test::read_raster(piece_path);
        ASSERT_FALSE(piece.values.empty()) << piece_path;
        EXPECT_EQ(piece.nodata, all.nodata);
        EXPECT_EQ(piece.transform[1], all.transform[1]);
        EXPECT_EQ(piece.transform[5], all.transform[5]);
        EXPECT_EQ(piece.crs_wkt, all.crs_wkt);
        const double col = (piece.transform[0] - all.transform[0]) / all.transform[1];
        const double row = (piece.transform[3] - all.transform[3]) / all.transform[5];
        ASSERT_NEAR(col, std::round(col), 1e-6) << piece_path;  // on the whole grid's lattice
        ASSERT_NEAR(row, std::round(row), 1e-6) << piece_path;
        const int c0 = static_cast<int>(std::lround(col)), r0 = static_cast<int>(std::lround(row));
        ASSERT_TRUE(c0 >= 0 && r0 >= 0 && c0 + piece.width <= all.width && r0 + piece.height <= all.height);
        for (int y = 0; y < piece.height; ++y) {
            const float* a = &all.values[static_cast<std::size_t>(r0 + y) * all.width + c0];
            const float* p = &piece.values[static_cast<std::size_t>(y) * piece.width];
            ASSERT_EQ(std::memcmp(a, p, sizeof(float) * piece.width), 0) << piece_path << " row " << y;
            for (int x = 0; x < piece.width; ++x) ++covered[static_cast<std::size_t>(r0 + y) * all.width + c0 + x];
        }
    }
};

TEST_F(DemBlocks, PiecesCoverTheGridOnceByPointCount) {
    const auto ds = dataset::open_dataset({survey("ky-jmo335-eastern-kentucky")});
    const raster::DemGrid grid = raster::make_dem_grid(raster::dataset_area(ds), 2.0, 384);
    const std::vector<double> points = raster::block_point_estimates(ds, grid);
    double estimated = 0, total = 0;
    for (const double p : points) estimated += p;
    for (const auto& t : ds.tiles) total += static_cast<double>(t.tile.header.point_count);
    EXPECT_NEAR(estimated, total, total * 1e-9);
    for (const int n : {1, 2, 3, 5, 7, 16, int(grid.all_blocks().count())}) {
        const auto pieces = raster::dem_block_pieces(ds, grid, n);
        ASSERT_EQ(pieces.size(), static_cast<std::size_t>(n));
        std::vector<int> seen(points.size(), 0);
        double heaviest = 0;
        for (const raster::BlockRange& b : pieces) {
            ASSERT_FALSE(b.empty());
            ASSERT_TRUE(grid.all_blocks().contains(b));
            double weight = 0;
            for (int iy = b.y0; iy <= b.y1; ++iy) {
                for (int ix = b.x0; ix <= b.x1; ++ix) {
                    ++seen[static_cast<std::size_t>(iy) * grid.blocks_x() + ix];
                    weight += points[static_cast<std::size_t>(iy) * grid.blocks_x() + ix];
                }
            }
            heaviest = std::max(heaviest, weight);
        }
        for (const int s : seen) ASSERT_EQ(s, 1) << n;
        if (n <= 7) {
            EXPECT_LT(heaviest, 2.0 * total / n) << n;  // about equal shares of the points (blocks of 768 m)
        }
        EXPECT_EQ(raster::dem_block_pieces(ds, grid, n), pieces);  // the same in every process
    }
    EXPECT_THROW(raster::dem_block_pieces(ds, grid, int(grid.all_blocks().count()) + 1), Error);
}

TEST_F(DemBlocks, ParsesIOfN) {
    EXPECT_EQ(raster::parse_block_piece("3/16"), std::make_pair(3, 16));
    EXPECT_EQ(raster::parse_block_piece("1/1"), std::make_pair(1, 1));
    for (const char* bad : {"0/4", "5/4", "3", "a/4", "3/", "/4", "-1/4", "2/4x"}) {
        EXPECT_THROW(raster::parse_block_piece(bad), Error) << bad;
    }
}

// The products of an unclassified survey, the dsm's TIN across the pieces' and the tiles' borders
// included, on its 9 tiles.
TEST_F(DemBlocks, ProductPiecesMosaicIntoTheWholeRun) {
    const auto ds = dataset::open_dataset({survey("ky-jmo335-eastern-kentucky")});
    raster::DemRequest r = request("whole.tif", 2.5);  // 3 x 3 blocks of 464 texels (the dsm's margin: 24)
    r.products = raster::products_from_names("dsm,density,pulse-density,intensity,count");
    const raster::DemResult whole = raster::make_dem(ds, r);
    ASSERT_GE(whole.grid.all_blocks().count(), 9);
    expect_pieces_equal_whole(ds, r, whole, 5);
}

// The dtm of every point at 5 m (65 points a texel: each block walks a thinned set first, proving
// its texels from the points near them), in pieces and whole.
TEST_F(DemBlocks, ThinnedDtmPiecesMosaicIntoTheWholeRun) {
    const auto ds = dataset::open_dataset({survey("ky-jmo335-eastern-kentucky")});
    raster::DemRequest r = request("whole.tif", 5.0);  // 2 x 2 blocks of 464 texels
    r.products = raster::products_from_names("dtm");
    r.product_options.dtm_classes = lidarscout::PointFilter::parse("0", "", "");
    r.product_options.classes_given = true;
    const raster::DemResult whole = raster::make_dem(ds, r);
    ASSERT_GE(whole.grid.all_blocks().count(), 4);
    expect_pieces_equal_whole(ds, r, whole, 3);
}

// The ground and water TIN of a classified tile, and the chm from it.
TEST_F(DemBlocks, ClassifiedDtmPiecesMosaicIntoTheWholeRun) {
    const auto ds = dataset::open_dataset({survey("ky-woodford-county")});
    raster::DemRequest r = request("whole.tif", 1.0);
    r.products = raster::products_from_names("dtm,chm");
    const raster::DemResult whole = raster::make_dem(ds, r);
    expect_pieces_equal_whole(ds, r, whole, 3);
}

// The dtm of two tiles of the unclassified survey from the ground filter (run per block on its
// points and margin, so a piece makes the same blocks as the whole run), and the chm from it.
TEST_F(DemBlocks, GroundFilteredDtmPiecesMosaicIntoTheWholeRun) {
    const std::string folder = survey("ky-jmo335-eastern-kentucky");
    const auto ds = dataset::open_dataset({folder + "/N117E379.laz", folder + "/N117E380.laz"});
    raster::DemRequest r = request("whole.tif", 1.0);
    r.products = raster::products_from_names("dtm,chm");
    recon::GroundFilterParams ground;
    ground.window_m = 6;  // fewer openings: this checks the stitching, not the terrain
    r.product_options.ground = ground;
    const raster::DemResult whole = raster::make_dem(ds, r);
    ASSERT_GE(whole.grid.all_blocks().count(), 4);
    expect_pieces_equal_whole(ds, r, whole, 2);
}

// The --from full methods (tin with a maximum edge, idw with a wide radius) on one tile.
TEST_F(DemBlocks, MethodPiecesMosaicIntoTheWholeRun) {
    const auto ds = dataset::open_dataset({survey("ky-woodford-county")});
    for (const auto method : {raster::DemMethod::Mean, raster::DemMethod::Max, raster::DemMethod::Idw,
                              raster::DemMethod::Tin}) {  // min: the same gridder as max
        SCOPED_TRACE(std::string(raster::dem_method_name(method)));
        raster::DemRequest r = request("whole.tif", 1.0);
        r.method = method;
        r.idw_radius_m = method == raster::DemMethod::Idw ? 4.0 : 0.0;
        r.tin_max_edge_m = method == raster::DemMethod::Tin ? 15.0 : 0.0;
        const raster::DemResult whole = raster::make_dem(ds, r);
        expect_pieces_equal_whole(ds, r, whole, 4);
    }
}

TEST_F(DemBlocks, WhatAPieceCannotMakeIsRefused) {
    const auto ds = dataset::open_dataset({survey("ky-woodford-county")});
    raster::DemRequest r = request("p.tif", 4.0);
    r.block_index = 1;
    r.block_count = 2;
    r.hillshade = path("h.png");
    EXPECT_THROW(raster::make_dem(ds, r), Error);
    r.hillshade.clear();
    r.contours_interval = 10;
    EXPECT_THROW(raster::make_dem(ds, r), Error);
    r.contours_interval = 0;
    r.source = raster::DemSource::Overview;
    r.method = raster::DemMethod::Linear;
    EXPECT_THROW(raster::make_dem(ds, r), Error);
    r.source = raster::DemSource::Full;
    r.method = raster::DemMethod::Mean;
    r.block_count = 100000;
    EXPECT_THROW(raster::make_dem(ds, r), Error);
    EXPECT_TRUE(std::filesystem::is_empty(dir));
}

}  // namespace
}  // namespace lidarscout
