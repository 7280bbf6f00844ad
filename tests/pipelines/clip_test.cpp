// pipelines::clip_to_file and read_region_points: real files of point formats 1, 3, 6 and 7 clipped
// by a polygon with a hole and a filter give the records a brute-force pass over the file keeps
// (count and SHA-256 of the records), and the clip decodes again through our decoder with the same
// SHA; header fields and VLRs kept (but liblas's copy of the WKT). On a grid of tiles only the
// touched tiles are decoded; tiles of mixed point formats are refused naming both; a corrupt tile
// is named and skipped. Tiles in two UTM zones clipped together are written in the frame's CRS
// (GeoTIFF keys for format 2, WKT for format 7), their points where a brute-force reprojection puts
// them, within the output's quantization; so are a tile in degrees and one in UTM 10N, clipped in
// degrees (scale 1e-7) or in metres.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cstdio>
#include <filesystem>
#include <string>
#include <vector>

#include "core/error.hpp"
#include "core/sha256.hpp"
#include "core/thread_pool.hpp"
#include "damaged_tile.hpp"
#include "geo/projection.hpp"
#include "dataset/dataset.hpp"
#include "dataset/point_reader.hpp"
#include "core/polygon.hpp"
#include "io/file.hpp"
#include "las_fixture.hpp"
#include "pipelines/clip.hpp"
#include "pipelines/tile_writer.hpp"
#include "temp_dir_fixture.hpp"
#include "test_data.hpp"

namespace lidarscout::pipelines {
namespace {

namespace fs = std::filesystem;

struct Records {
    std::uint64_t count = 0;
    std::string sha;
};

// Every record of a one-tile dataset's tile that `keep` keeps (decoded in file units), hashed.
template <class Keep>
Records brute_force(const dataset::Tile& tile, Keep&& keep) {
    Sha256 sha;
    Records out;
    const auto& f = las::point_format_info(tile.header.point_format);
    const std::size_t n = tile.header.record_length;
    dataset::for_each_record_batch(io::File::open(tile.path()), tile, ThreadPool::shared(),
                                   [&](std::uint64_t, std::span<const std::uint8_t> records) {
                                       for (std::size_t k = 0; k + n <= records.size(); k += n) {
                                           const auto r = records.subspan(k, n);
                                           if (!keep(las::decode_point(r, f, tile.header))) continue;
                                           sha.update(r);
                                           ++out.count;
                                       }
                                   });
    out.sha = sha.hex_digest();
    return out;
}

Records all_records(const std::string& path) {
    const auto ds = dataset::open_dataset({path});
    EXPECT_EQ(ds.tiles.size(), 1u);
    return brute_force(ds.tiles.at(0).tile, [](const las::Point&) { return true; });
}

// A square over the middle 80% of the tile with a square hole over the middle 20%, as WKT.
std::string polygon_with_hole(const las::Header& h) {
    const auto at = [&](int axis, double t) { return h.min[axis] + t * (h.max[axis] - h.min[axis]); };
    const auto ring = [&](double a, double b) {
        char s[256];
        std::snprintf(s, sizeof s, "(%.4f %.4f, %.4f %.4f, %.4f %.4f, %.4f %.4f)", at(0, a), at(1, a), at(0, b),
                      at(1, a), at(0, b), at(1, b), at(0, a), at(1, b));
        return std::string(s);
    };
    return "POLYGON (" + ring(0.1, 0.9) + ", " + ring(0.4, 0.6) + ")";
}

class ClipFormats : public test::TempDirTest, public ::testing::WithParamInterface<const char*> {};

TEST_P(ClipFormats, RecordsEqualABruteForcePolygonFilter) {
    const std::string source = (test::formats_dir() / GetParam()).string();
    const auto ds = dataset::open_dataset({source});
    ASSERT_EQ(ds.tiles.size(), 1u) << (ds.skipped.empty() ? "" : ds.skipped[0].error);
    const auto& tile = ds.tiles[0].tile;
    const MultiPolygon polygon = parse_wkt_polygon(polygon_with_hole(tile.header));
    ClipRequest request;
    request.output = path("clip.laz");
    request.region = polygon_region(polygon);
    request.filter = PointFilter::parse("", "", "1-");  // intensity 0 left out
    const ClipResult r = clip_to_file(ds, request, ThreadPool::shared());

    const Records expected = brute_force(tile, [&](const las::Point& p) {
        return p.intensity >= 1 && polygon.contains(p.x, p.y);
    });
    EXPECT_GT(expected.count, 0u);
    EXPECT_LT(expected.count, tile.header.point_count);
    EXPECT_EQ(r.points_written, expected.count);
    EXPECT_EQ(r.read.points_read, tile.header.point_count);
    EXPECT_EQ(r.read.tiles_decoded, 1u);
    const Records written = all_records(request.output);
    EXPECT_EQ(written.count, expected.count);
    EXPECT_EQ(written.sha, expected.sha);

    const auto out = dataset::open_dataset({request.output});
    const auto& h = out.tiles.at(0).tile.header;
    EXPECT_EQ(h.point_format, tile.header.point_format);
    EXPECT_EQ(h.record_length, tile.header.record_length);
    EXPECT_EQ(h.scale, tile.header.scale);
    EXPECT_EQ(h.offset, tile.header.offset);
    EXPECT_EQ(h.version_string(), tile.header.version_string());
    EXPECT_EQ(h.system_identifier, tile.header.system_identifier);
    EXPECT_EQ(out.tiles[0].tile.crs().epsg, tile.crs().epsg);
    const auto liblas_copies = std::count_if(tile.vlrs().begin(), tile.vlrs().end(), [](const las::Vlr& v) {
        return v.user_id == "liblas";  // the WKT again, beside the LASF_Projection one: dropped
    });
    EXPECT_EQ(out.tiles[0].tile.vlrs().size() + liblas_copies, tile.vlrs().size() + (tile.compressed() ? 0 : 1));
    EXPECT_EQ(out.frame.crs, ds.frame.crs);
    EXPECT_GE(h.min[0], polygon.min_x() - 1e-6);
    EXPECT_LE(h.max[0], polygon.max_x() + 1e-6);
}

INSTANTIATE_TEST_SUITE_P(
    PointFormats1367, ClipFormats,
    ::testing::Values("r-lidar__lidR/inst__extdata__Topography.laz", "PDAL__PDAL/test__data__laz__autzen_trim.laz",
                      "IGNF__ctview/data__las__classee__test_data_77050_627755_LA93_IGN69.las",
                      "PDAL__PDAL/test__data__las__autzen_trim_7.las"));

// A 3 x 3 grid of 100 m tiles (a point every 5 m), each with its own offset.
class ClipGrid : public test::TempDirTest {
protected:
    void SetUp() override {
        TempDirTest::SetUp();
        for (int ty = 0; ty < 3; ++ty) {
            for (int tx = 0; tx < 3; ++tx) {
                std::vector<test::FixturePoint> points;
                for (int i = 0; i < 20; ++i) {
                    for (int j = 0; j < 20; ++j) {
                        const double x = 500000 + tx * 100 + i * 5 + 1.25, y = 4200000 + ty * 100 + j * 5 + 1.25;
                        points.push_back({x, y, 100 + 0.01 * i, static_cast<std::uint8_t>(j % 2 ? 2 : 5)});
                    }
                }
                tiles.push_back(path(("t" + std::to_string(tx) + std::to_string(ty) + ".laz").c_str()));
                test::write_fixture(tiles.back(), points, 32616, true, 100);
            }
        }
    }
    std::vector<std::string> tiles;
};

TEST_F(ClipGrid, OnlyTouchedTilesAreDecoded) {
    const auto ds = dataset::open_dataset(tiles);
    ASSERT_EQ(ds.tiles.size(), 9u);
    ClipRequest request;
    request.output = path("out.las");
    // Across the border of tiles (0,0) and (1,0) only; classes 2.
    request.region = box_region(500090, 4200010, 500110, 4200030);
    request.filter = PointFilter::parse("2", "", "");
    const ClipResult r = clip_to_file(ds, request, ThreadPool::shared());
    EXPECT_EQ(r.read.tiles_touched.size(), 2u);
    EXPECT_EQ(r.read.tiles_decoded, 2u);
    EXPECT_EQ(r.read.points_read, 800u);
    // x in {91.25, 96.25, 101.25, 106.25}, y in {11.25, 16.25, 21.25, 26.25}, j odd (class 2): y 16.25, 26.25.
    EXPECT_EQ(r.points_written, 8u);
    const auto out = dataset::open_dataset({request.output});
    const auto points = test::read_points_back(out);
    ASSERT_EQ(points.size(), 8u);
    for (const auto& p : points) {  // re-quantized exactly from the second tile's offset
        EXPECT_GE(p[0], 500090);
        EXPECT_LE(p[0], 500110);
        const double fx = p[0] - 1.25 - 500000, fy = p[1] - 1.25 - 4200000;
        EXPECT_DOUBLE_EQ(fx / 5, std::round(fx / 5));
        EXPECT_DOUBLE_EQ(fy / 5, std::round(fy / 5));
    }
}

TEST_F(ClipGrid, APolygonDecodesOnlyTheTilesItTouches) {
    const auto ds = dataset::open_dataset(tiles);
    ClipRequest request;
    request.output = path("out.laz");
    // A thin quadrilateral along the diagonal from tile (0,0) to tile (2,2): its box covers all 9 tiles.
    request.region = polygon_region(parse_wkt_polygon(
        "POLYGON ((500010 4200008, 500295 4200293, 500293 4200295, 500008 4200010))"));
    const ClipResult r = clip_to_file(ds, request, ThreadPool::shared());
    EXPECT_EQ(r.read.tiles_touched.size(), 3u);
    EXPECT_EQ(r.read.tiles_decoded, 3u);
    EXPECT_EQ(r.read.points_read, 3 * 400u);
    EXPECT_GT(r.points_written, 0u);
}

TEST_F(ClipGrid, MissingTileIsNamedAndSkipped) {
    const auto ds = dataset::open_dataset(tiles);
    fs::remove(tiles[4]);  // tile (1,1) gone after the dataset was opened
    ClipRequest request;
    request.output = path("out.laz");
    request.region = box_region(500000, 4200000, 500300, 4200300);
    const ClipResult r = clip_to_file(ds, request, ThreadPool::shared());
    EXPECT_EQ(r.points_written, 8 * 400u);
    EXPECT_EQ(r.read.tiles_decoded, 8u);
    ASSERT_EQ(r.read.skipped.size(), 1u);
    EXPECT_NE(r.read.skipped[0].file.find("t11.laz"), std::string::npos);
    EXPECT_EQ(r.read.points_skipped, 400u);
}

TEST_F(ClipGrid, CorruptChunkIsNamedAndSkipped) {
    const auto damaged = test::damaged_tile(dir);
    const auto ds = dataset::open_dataset({damaged.string()});
    const auto& h = ds.tiles.at(0).tile.header;
    ClipRequest request;
    request.output = path("out.laz");
    request.region = box_region(h.min[0], h.min[1], h.max[0], h.max[1]);
    const ClipResult r = clip_to_file(ds, request, ThreadPool::shared());
    ASSERT_EQ(r.read.skipped.size(), 1u);
    EXPECT_NE(r.read.skipped[0].file.find("damaged.laz"), std::string::npos);
    EXPECT_EQ(r.read.points_skipped, test::kDamagedChunkPoints);
    EXPECT_EQ(r.points_written, h.point_count - test::kDamagedChunkPoints);
}

TEST_F(ClipGrid, MixedPointFormatsAreRefusedNamingBoth) {
    const std::string other = (test::formats_dir() / "PDAL__PDAL/test__data__laz__autzen_trim.laz").string();
    const auto autzen = dataset::open_dataset({other});
    const auto& h = autzen.tiles.at(0).tile.header;
    // A fixture tile without a CRS (taken to be in the frame's, in metres) on autzen's area (in feet).
    const double f = autzen.frame.xy_to_metres;
    std::vector<test::FixturePoint> points = {{(h.min[0] + 10) * f, (h.min[1] + 10) * f, h.min[2]}};
    write_fixture(path("moved.las"), points, 0);
    const auto ds = dataset::open_dataset({other, path("moved.las")});
    ASSERT_EQ(ds.tiles.size(), 2u);
    ClipRequest request;
    request.output = path("out.laz");
    request.region = box_region(h.min[0], h.min[1], h.max[0], h.max[1]);
    try {
        clip_to_file(ds, request, ThreadPool::shared());
        FAIL() << "mixed formats were not refused";
    } catch (const Error& e) {
        const std::string what = e.what();
        EXPECT_NE(what.find("autzen_trim.laz (format 3"), std::string::npos) << what;
        EXPECT_NE(what.find("moved.las (format 2"), std::string::npos) << what;
    }
    EXPECT_FALSE(fs::exists(request.output));
}

// Two tiles side by side on a 5 m grid: west.las in EPSG:32632 (x 500000-500100), east.las made in
// EPSG:32632 (x 500100-500200) and written in EPSG:32633; as LAS 1.2 format 2 (GeoTIFF keys) or
// converted to LAS 1.4 format 7 (WKT). Clipped with the frame in GetParam()'s CRS.
struct MixedCrsCase {
    const char* frame;
    int format;
};

// A 20 x 20 grid of 5 m from (x0, y0), heights rising to the north-east.
std::vector<test::FixturePoint> grid_at(double x0, double y0) {
    std::vector<test::FixturePoint> points;
    for (int i = 0; i < 20; ++i) {
        for (int j = 0; j < 20; ++j) points.push_back({x0 + i * 5 + 1.25, y0 + j * 5 + 1.25, 100.0 + i + j});
    }
    return points;
}

// `points` moved from the CRS `from` into `to`.
std::vector<test::FixturePoint> placed(std::vector<test::FixturePoint> points, const char* from, const char* to) {
    std::vector<double> x, y;
    for (const auto& p : points) x.push_back(p.x), y.push_back(p.y);
    geo::CrsTransform(from, to).apply(x, y, {});
    for (std::size_t i = 0; i < points.size(); ++i) points[i].x = x[i], points[i].y = y[i];
    return points;
}

// The points of each tile (read alone, in its own CRS) placed in `frame`, in dataset order, that lie in
// `polygon`.
std::vector<std::array<double, 3>> placed_in(const std::vector<std::string>& tiles, const std::string& frame,
                                             const MultiPolygon& polygon) {
    std::vector<std::array<double, 3>> out;
    dataset::DatasetOptions in_its_crs;
    in_its_crs.accept_degrees = true;
    for (const auto& t : tiles) {
        const auto alone = dataset::open_dataset({t}, in_its_crs);
        auto points = test::read_points_back(alone);
        std::vector<double> x, y;
        for (const auto& p : points) x.push_back(p[0]), y.push_back(p[1]);
        if (alone.frame.crs != frame) geo::CrsTransform(alone.frame.crs, frame).apply(x, y, {});
        for (std::size_t i = 0; i < points.size(); ++i) {
            if (polygon.contains(x[i], y[i])) out.push_back({x[i], y[i], points[i][2]});
        }
    }
    return out;
}

// The box as a polygon.
MultiPolygon box_polygon(double x0, double y0, double x1, double y1) {
    return MultiPolygon({{Ring{{x0, y0}, {x1, y0}, {x1, y1}, {x0, y1}}}});
}

class ClipMixedCrs : public test::TempDirTest, public ::testing::WithParamInterface<MixedCrsCase> {
protected:
    void SetUp() override {
        TempDirTest::SetUp();
        test::write_fixture(path("west.las"), grid_at(500000, 5400000), 32632);
        test::write_fixture(path("east.las"), placed(grid_at(500100, 5400000), "EPSG:32632", "EPSG:32633"), 32633);
        tiles = {path("west.las"), path("east.las")};
        if (GetParam().format == 7) {
            ConvertOptions options;
            options.point_format = 7;
            for (auto& t : tiles) {
                const std::string converted = t.substr(0, t.size() - 4) + "7.laz";
                convert_tile(t, converted, options, ThreadPool::shared());
                t = converted;
            }
        }
    }

    std::vector<std::string> tiles;
};

TEST_P(ClipMixedCrs, PointsAreWrittenReprojectedIntoTheFramesCrs) {
    const std::string frame = GetParam().frame;
    dataset::DatasetOptions options;
    options.crs = frame;
    const auto ds = dataset::open_dataset(tiles, options);
    ASSERT_EQ(ds.tiles.size(), 2u);
    ASSERT_TRUE(ds.tiles[0].to_frame || ds.tiles[1].to_frame);
    // Across both tiles: a quadrilateral drawn in EPSG:32632, its corners placed in the frame's CRS.
    std::vector<double> x = {500050, 500150, 500160, 500040}, y = {5400010, 5400005, 5400090, 5400080};
    if (frame != "EPSG:32632") geo::CrsTransform("EPSG:32632", frame).apply(x, y, {});
    Ring ring;
    for (std::size_t i = 0; i < x.size(); ++i) ring.push_back({x[i], y[i]});
    const MultiPolygon polygon({{ring}});
    ClipRequest request;
    request.output = path("out.laz");
    request.region = polygon_region(polygon);
    const ClipResult r = clip_to_file(ds, request, ThreadPool::shared());
    EXPECT_EQ(r.read.tiles_decoded, 2u);
    ASSERT_FALSE(r.notes.empty());
    EXPECT_NE(r.notes.back().find("reprojected into " + frame), std::string::npos) << r.notes.back();

    const auto expected = placed_in(tiles, frame, polygon);
    ASSERT_GT(expected.size(), 100u);
    EXPECT_EQ(r.points_written, expected.size());
    const auto out = dataset::open_dataset({request.output});
    ASSERT_EQ(out.tiles.size(), 1u);
    EXPECT_EQ(out.frame.crs, frame);
    const auto& h = out.tiles[0].tile.header;
    EXPECT_EQ(h.point_format, GetParam().format);
    EXPECT_EQ(h.scale[0], 0.001);
    EXPECT_EQ(out.tiles[0].tile.crs().source, GetParam().format == 7 ? "wkt" : "geotiff");
    const auto written = test::read_points_back(out);
    ASSERT_EQ(written.size(), expected.size());
    for (std::size_t i = 0; i < written.size(); ++i) {
        for (int a = 0; a < 3; ++a) ASSERT_NEAR(written[i][a], expected[i][a], 0.0005 + 1e-7) << i << " " << a;
        EXPECT_GE(written[i][0], h.min[0]);
        EXPECT_LE(written[i][1], h.max[1]);
    }
}

// The frame in the first tile's CRS (its scale/offset kept), in the second's, and in neither (chosen).
INSTANTIATE_TEST_SUITE_P(Frames, ClipMixedCrs,
                         ::testing::Values(MixedCrsCase{"EPSG:32632", 2}, MixedCrsCase{"EPSG:32633", 2},
                                           MixedCrsCase{"EPSG:25832", 2}, MixedCrsCase{"EPSG:32632", 7}));

// Near Autzen (Oregon, UTM zone 10N): utm.las, a 20 x 20 grid of 5 m in EPSG:32610, and degrees.las, the
// same grid 100 m east placed in longitude/latitude (GeoTIFF keys of EPSG:4326, scale 1e-7 degree).
class ClipDegrees : public test::TempDirTest {
protected:
    void SetUp() override {
        TempDirTest::SetUp();
        test::write_fixture(path("utm.las"), grid_at(494000, 4878000), 32610);
        test::write_fixture(path("degrees.las"), placed(grid_at(494100, 4878000), "EPSG:32610", "EPSG:4326"),
                            test::FixtureCrs{4326, 0, true, 1e-7});
    }

    // Clips `tiles` opened in `frame` (accepting degrees) to the box across both grids (drawn in UTM 10N,
    // as the frame has it); checks the points against placed_in and returns the output, read back.
    dataset::Dataset clip(const std::vector<std::string>& tiles, const std::string& frame) {
        dataset::DatasetOptions options;
        options.crs = frame;
        options.accept_degrees = true;
        const auto ds = dataset::open_dataset(tiles, options);
        EXPECT_EQ(ds.tiles.size(), tiles.size());
        std::vector<double> x = {494050, 494150}, y = {4878010, 4878080};
        if (frame != "EPSG:32610") geo::CrsTransform("EPSG:32610", frame).apply(x, y, {});
        const MultiPolygon box = box_polygon(x[0], y[0], x[1], y[1]);
        ClipRequest request;
        request.output = path("out.las");
        request.region = polygon_region(box);
        const ClipResult r = clip_to_file(ds, request, ThreadPool::shared());
        const auto expected = placed_in(tiles, frame, box);
        EXPECT_GT(expected.size(), 100u);
        EXPECT_EQ(r.points_written, expected.size());
        auto out = dataset::open_dataset({request.output}, options);
        const auto written = test::read_points_back(out);
        EXPECT_EQ(written.size(), expected.size());
        const double tolerance = out.tiles.at(0).tile.header.scale[0] / 2 + 1e-9;
        for (std::size_t i = 0; i < written.size() && i < expected.size(); ++i) {
            EXPECT_NEAR(written[i][0], expected[i][0], tolerance) << i;
            EXPECT_NEAR(written[i][1], expected[i][1], tolerance) << i;
        }
        return out;
    }
};

TEST_F(ClipDegrees, ClippedInDegrees) {
    const auto out = clip({path("utm.las"), path("degrees.las")}, "EPSG:4326");
    const auto& t = out.tiles.at(0).tile;
    EXPECT_TRUE(out.frame.geographic);
    EXPECT_TRUE(t.crs().geographic);
    EXPECT_EQ(t.crs().epsg, 4326);
    EXPECT_EQ(t.header.scale[0], 1e-7);  // degrees.las's, the tile stored in the frame
    const auto only_utm = clip({path("utm.las")}, "EPSG:4326");  // scale and offset chosen for degrees
    const auto& h = only_utm.tiles.at(0).tile.header;
    EXPECT_EQ(h.scale[0], 1e-7);
    EXPECT_EQ(h.offset[0], -123.0);
    EXPECT_EQ(h.offset[1], 44.0);
}

TEST_F(ClipDegrees, ClippedReprojectedIntoMetres) {
    const auto out = clip({path("utm.las"), path("degrees.las")}, "EPSG:32610");
    const auto& t = out.tiles.at(0).tile;
    EXPECT_FALSE(out.frame.geographic);
    EXPECT_EQ(t.crs().epsg, 32610);
    EXPECT_EQ(t.header.scale[0], 0.001);
}

TEST_F(ClipDegrees, DegreesAreSkippedNamingTheZoneUnlessAccepted) {
    const auto skipped = dataset::open_dataset({path("degrees.las")});
    EXPECT_TRUE(skipped.tiles.empty());
    ASSERT_EQ(skipped.skipped.size(), 1u);
    EXPECT_NE(skipped.skipped[0].error.find("give --crs EPSG:32610 (WGS 84 / UTM zone 10N, at the data's centre)"),
              std::string::npos) << skipped.skipped[0].error;
    dataset::DatasetOptions options;
    options.accept_degrees = true;
    const auto accepted = dataset::open_dataset({path("degrees.las")}, options);
    ASSERT_EQ(accepted.tiles.size(), 1u);
    EXPECT_TRUE(accepted.frame.geographic);
    EXPECT_EQ(accepted.frame.crs, "EPSG:4326");
    EXPECT_TRUE(accepted.warnings.empty()) << accepted.warnings[0].message;  // no "taken as metres"
    options = {};
    options.crs = "EPSG:4326";
    EXPECT_THROW(dataset::open_dataset({path("utm.las")}, options), Error);  // degrees asked, not accepted
}

}  // namespace
}  // namespace lidarscout::pipelines
