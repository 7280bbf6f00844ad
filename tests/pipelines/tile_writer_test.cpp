// convert_tile: LAS->LAZ->LAS is lossless (but for liblas's copy of the CRS), LAZ chunks equal the
// reference encoder's, format conversion keeps coordinates, the output appears atomically and never replaces the input;
// values the target format cannot hold are refused with their count, or written clamped when forced.
#include <gtest/gtest.h>

#include <unistd.h>

#include <fstream>

#include "core/error.hpp"
#include "core/sha256.hpp"
#include "core/thread_pool.hpp"
#include "dataset/point_reader.hpp"
#include "dataset/tile.hpp"
#include "geo/crs_definition.hpp"
#include "pipelines/tile_writer.hpp"
#include "las/point_format.hpp"
#include "io/file.hpp"
#include "test_data.hpp"

namespace lidarscout {
namespace {

namespace fs = std::filesystem;

class TileWriter : public ::testing::Test {
protected:
    fs::path dir = fs::temp_directory_path() / ("lidarscout_writer_" + std::to_string(::getpid()));
    ThreadPool pool{2};

    void SetUp() override { fs::create_directories(dir); }
    void TearDown() override { fs::remove_all(dir); }

    std::string out(const char* name) const { return (dir / name).string(); }

    std::string checksum(const std::string& path) {
        auto file = io::File::open(path);
        auto tile = dataset::read_tile(file);
        Sha256 sha;
        dataset::for_each_record_batch(file, tile, pool,
                                       [&](std::uint64_t, std::span<const std::uint8_t> r) { sha.update(r); });
        return sha.hex_digest();
    }
};

TEST_F(TileWriter, LasToLazToLasIsLossless) {
    const auto las = (test::formats_dir() / "PDAL__PDAL/test__data__las__autzen_trim.las").string();
    pipelines::ConvertOptions opt;
    auto r = pipelines::convert_tile(las, out("a.laz"), opt, pool);
    EXPECT_EQ(r.points, 110000u);
    EXPECT_EQ(r.chunks, 3u);
    opt.compress = false;
    pipelines::convert_tile(out("a.laz"), out("b.las"), opt, pool);
    EXPECT_EQ(checksum(out("a.laz")), checksum(las));
    EXPECT_EQ(checksum(out("b.las")), checksum(las));
    // Same header fields as the input (except the format's compression bit / offsets).
    auto in_tile = dataset::read_tile(io::File::open(las));
    auto out_tile = dataset::read_tile(io::File::open(out("b.las")));
    EXPECT_EQ(out_tile.header.point_count, in_tile.header.point_count);
    EXPECT_EQ(out_tile.header.min, in_tile.header.min);
    EXPECT_EQ(out_tile.header.scale, in_tile.header.scale);
    EXPECT_EQ(out_tile.vlrs().size(), in_tile.vlrs().size() - 1);  // liblas's copy of the WKT dropped
    EXPECT_EQ(out_tile.crs().epsg, in_tile.crs().epsg);
    EXPECT_EQ(geo::crs_definition(out_tile.crs()), geo::crs_definition(in_tile.crs()));  // (its WKT)
}

TEST_F(TileWriter, LazChunksEqualReferenceEncoder) {
    const auto las = (test::formats_dir() / "PDAL__PDAL/test__data__las__autzen_trim.las").string();
    const auto ref = (test::formats_dir() / "PDAL__PDAL/test__data__laz__autzen_trim.laz").string();
    pipelines::convert_tile(las, out("a.laz"), {}, pool);
    auto mine = io::File::open(out("a.laz"));
    auto theirs = io::File::open(ref);
    auto a = dataset::read_tile(mine), b = dataset::read_tile(theirs);
    ASSERT_EQ(a.chunks()->size(), b.chunks()->size());
    for (std::size_t i = 0; i < a.chunks()->size(); ++i) {
        const auto& ca = (*a.chunks())[i];
        const auto& cb = (*b.chunks())[i];
        ASSERT_EQ(ca.byte_size, cb.byte_size);
        EXPECT_TRUE(mine.read_vector(ca.byte_offset, ca.byte_size) == theirs.read_vector(cb.byte_offset, cb.byte_size));
    }
}

TEST_F(TileWriter, VariableChunksAndSmallChunks) {
    const auto laz = (test::formats_dir() / "PDAL__PDAL/test__data__laz__autzen_trim.laz").string();
    pipelines::ConvertOptions opt;
    opt.chunk_size = 7'000;
    opt.variable_chunks = true;
    auto r = pipelines::convert_tile(laz, out("v.laz"), opt, pool);
    EXPECT_EQ(r.chunks, 16u);  // ceil(110000 / 7000)
    auto tile = dataset::read_tile(io::File::open(out("v.laz")));
    EXPECT_TRUE(tile.laz()->variable_chunks());
    EXPECT_EQ(tile.chunks()->back().point_count, 110000u - 15 * 7000u);
    EXPECT_EQ(checksum(out("v.laz")), checksum(laz));
}

TEST_F(TileWriter, ValuesTheFormatCannotHoldAreRefusedOrForcedWithACount) {
    const auto las = (test::formats_dir() / "PDAL__PDAL/test__data__las__autzen_trim.las").string();  // format 3
    pipelines::ConvertOptions opt;
    opt.compress = false;
    opt.point_format = 7;
    pipelines::convert_tile(las, out("f7.las"), opt, pool);
    const auto header = [](const std::string& path) { return dataset::read_tile(io::File::open(path)).header; };
    const auto h7 = header(out("f7.las"));
    opt.point_format = 3;  // the control: back to the input's format, nothing lost
    EXPECT_TRUE(pipelines::convert_tile(out("f7.las"), out("f3.las"), opt, pool).warnings.empty());
    {  // three points of class 34, which formats 0-5 cannot hold
        std::fstream f(out("f7.las"), std::ios::in | std::ios::out | std::ios::binary);
        for (std::uint64_t i : {1ull, 500ull, 109999ull}) {
            f.seekp(static_cast<std::streamoff>(h7.offset_to_point_data + i * h7.record_length + 16));
            f.put(34);
        }
    }
    try {
        opt.point_format = 1;  // no colour either: every coloured point loses it
        pipelines::convert_tile(out("f7.las"), out("f1.las"), opt, pool);
        ADD_FAILURE() << "class 34 written into format 1 without a word";
    } catch (const Error& e) {
        const std::string m = e.what();
        EXPECT_NE(m.find("point format 1 cannot hold 3 points with a class above 31"), std::string::npos) << m;
        EXPECT_NE(m.find("points with a colour (dropped)"), std::string::npos) << m;
        EXPECT_NE(m.find("--force"), std::string::npos) << m;
    }
    EXPECT_FALSE(fs::exists(out("f1.las")));
    opt.force = true;
    const auto forced = pipelines::convert_tile(out("f7.las"), out("f1.las"), opt, pool);
    ASSERT_EQ(forced.warnings.size(), 1u);
    EXPECT_NE(forced.warnings[0].find("3 points with a class above 31 (written as 31)"), std::string::npos);
    auto f1 = io::File::open(out("f1.las"));
    const auto h1 = dataset::read_tile(f1).header;
    std::vector<std::uint8_t> record(h1.record_length);
    f1.read_exact(h1.offset_to_point_data + 500 * record.size(), record);
    EXPECT_EQ(las::decode_point(record, las::point_format_info(1), h1).classification, 31);
}

TEST_F(TileWriter, Formats6To10GetTheCrsAsWkt) {
    // 4_6_crop.las: GeoTIFF keys for EPSG:2903 + 5103 (a vertical code PROJ lacks), global encoding 0.
    const auto las = (test::formats_dir() / "PDAL__PDAL/test__data__las__4_6_crop.las").string();
    pipelines::ConvertOptions opt;
    opt.compress = false;
    opt.point_format = 3;  // the control: a legacy format keeps the keys
    pipelines::convert_tile(las, out("f3.las"), opt, pool);
    opt.point_format = 7;
    const auto result = pipelines::convert_tile(las, out("f7.las"), opt, pool);
    const auto f3 = dataset::read_tile(io::File::open(out("f3.las")));
    const auto f7 = dataset::read_tile(io::File::open(out("f7.las")));
    EXPECT_EQ(f3.header.global_encoding & 0x10, 0);
    EXPECT_EQ(f3.crs().source, "geotiff");
    EXPECT_EQ(f7.header.global_encoding & 0x10, 0x10);
    EXPECT_EQ(f7.crs().source, "wkt");
    EXPECT_EQ(f7.crs().epsg, 2903);
    EXPECT_EQ(f7.crs().horizontal_unit, las::LinearUnit::UsSurveyFoot);
    EXPECT_TRUE(f7.crs().warnings.empty());
    for (const auto& v : f7.vlrs()) EXPECT_FALSE(v.user_id == "LASF_Projection" && v.record_id == 34735);
    ASSERT_EQ(result.warnings.size(), 1u);  // the vertical code the WKT cannot name
    EXPECT_NE(result.warnings[0].find("vertical CRS EPSG:5103"), std::string::npos) << result.warnings[0];
}

TEST_F(TileWriter, FormatConversionKeepsCoordinatesAndColour) {
    const auto las = (test::formats_dir() / "PDAL__PDAL/test__data__las__autzen_trim.las").string();  // format 3
    pipelines::ConvertOptions opt;
    opt.compress = false;
    opt.point_format = 7;
    pipelines::convert_tile(las, out("f7.las"), opt, pool);
    auto in_file = io::File::open(las);
    auto out_file = io::File::open(out("f7.las"));
    auto in = dataset::read_tile(in_file), o = dataset::read_tile(out_file);
    EXPECT_EQ(o.header.point_format, 7);
    EXPECT_EQ(o.header.version_string(), "1.4");
    EXPECT_EQ(o.header.point_count, 110000u);
    std::vector<std::uint8_t> a(in.header.record_length), b(o.header.record_length);
    for (std::uint64_t i : {0ull, 12345ull, 109999ull}) {
        in_file.read_exact(in.header.offset_to_point_data + i * a.size(), a);
        out_file.read_exact(o.header.offset_to_point_data + i * b.size(), b);
        auto p = las::decode_point(a, las::point_format_info(3), in.header);
        auto q = las::decode_point(b, las::point_format_info(7), o.header);
        EXPECT_EQ(p.X, q.X);
        EXPECT_EQ(p.Z, q.Z);
        EXPECT_EQ(p.gps_time, q.gps_time);
        EXPECT_EQ(p.rgb, q.rgb);
        EXPECT_EQ(p.classification, q.classification);
        EXPECT_EQ(p.return_number, q.return_number);
    }
}

TEST_F(TileWriter, NeverOverwritesTheInputAndLeavesNoHalfFile) {
    const auto src = (test::formats_dir() / "PDAL__PDAL/test__data__las__autzen_trim.las").string();
    fs::copy_file(src, out("in.las"));
    pipelines::ConvertOptions opt;
    opt.compress = false;
    EXPECT_THROW(pipelines::convert_tile(out("in.las"), out("in.las"), opt, pool), Error);
    EXPECT_EQ(checksum(out("in.las")), checksum(src));
    // A failing conversion (a broken input) leaves nothing under the output name.
    const auto broken = (test::formats_dir() / "PDAL__PDAL/test__data__las__1.2-with-color-clipped.las").string();
    EXPECT_THROW(pipelines::convert_tile(broken, out("x.laz"), {}, pool), Error);
    EXPECT_FALSE(fs::exists(out("x.laz")));
    for (const auto& e : fs::directory_iterator(dir)) {
        EXPECT_EQ(e.path().filename().string().find(".tmp-"), std::string::npos);
    }
}

}  // namespace
}  // namespace lidarscout
