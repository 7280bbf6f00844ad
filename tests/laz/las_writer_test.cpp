// LasWriter: LAS and LAZ files written from raw records read back identically (header,
// VLRs, EVLRs, records), chunking does not depend on how records are handed over, and an
// unfinished file never appears.
#include <gtest/gtest.h>

#include <unistd.h>

#include <filesystem>
#include <fstream>

#include "core/error.hpp"
#include "core/thread_pool.hpp"
#include "laz/laz.hpp"
#include "dataset/point_reader.hpp"
#include "dataset/tile.hpp"
#include "io/file.hpp"
#include "las/header_writer.hpp"
#include "las/point_format.hpp"

namespace lidarscout {
namespace {

namespace fs = std::filesystem;

class LasWriter : public ::testing::Test {
protected:
    fs::path dir = fs::temp_directory_path() / ("lidarscout_las_writer_" + std::to_string(::getpid()));
    ThreadPool pool{2};

    void SetUp() override { fs::create_directories(dir); }
    void TearDown() override { fs::remove_all(dir); }
    std::string out(const char* name) const { return (dir / name).string(); }

    static las::Header header(std::uint8_t format) {
        las::Header h;
        h.version_major = 1;
        h.version_minor = 4;
        h.header_size = las::standard_header_size(1, 4);
        h.point_format = format;
        h.record_length = las::point_format_info(format).size;
        h.scale = {0.01, 0.01, 0.01};
        h.offset = {1000, 2000, 0};
        h.generating_software = "las writer test";
        return h;
    }

    // n records of `format` with varied fields (a smooth walk, as real scans are).
    static std::vector<std::uint8_t> records(std::uint8_t format, std::size_t n) {
        const auto& f = las::point_format_info(format);
        std::vector<std::uint8_t> out(n * f.size);
        for (std::size_t i = 0; i < n; ++i) {
            las::Point p;
            p.X = static_cast<std::int32_t>(i * 7 % 5000);
            p.Y = static_cast<std::int32_t>(i / 3);
            p.Z = static_cast<std::int32_t>(1000 + (i * 13) % 97);
            p.intensity = static_cast<std::uint16_t>(i * 31);
            p.return_number = 1;
            p.number_of_returns = 1;
            p.classification = static_cast<std::uint8_t>(2 + i % 4);
            p.gps_time = 1000.0 + i * 1e-4;
            p.rgb = {static_cast<std::uint16_t>(i), static_cast<std::uint16_t>(2 * i),
                     static_cast<std::uint16_t>(3 * i)};
            p.point_source_id = 7;
            las::encode_point(p, f, std::span(out).subspan(i * f.size, f.size));
        }
        return out;
    }

    std::vector<std::uint8_t> read_back(const std::string& path) {
        auto file = io::File::open(path);
        auto tile = dataset::read_tile(file);
        std::vector<std::uint8_t> all;
        dataset::for_each_record_batch(file, tile, pool, [&](std::uint64_t, std::span<const std::uint8_t> r) {
            all.insert(all.end(), r.begin(), r.end());
        });
        return all;
    }

    static std::vector<char> bytes(const std::string& path) {
        std::ifstream in(path, std::ios::binary);
        return {std::istreambuf_iterator<char>(in), {}};
    }
};

las::Vlr vlr(const char* user, std::uint16_t id, std::string payload, bool extended = false) {
    las::Vlr v;
    v.user_id = user;
    v.record_id = id;
    v.description = "test record";
    v.extended = extended;
    v.data.assign(payload.begin(), payload.end());
    return v;
}

TEST_F(LasWriter, LasWithVlrsAndEvlrsReadsBack) {
    const auto recs = records(7, 1234);
    laz::LasWriterOptions opt;
    opt.compress = false;
    laz::LasWriter w(out("a.las"), header(7), {vlr("test", 1, "hello")}, opt, pool);
    w.add(recs);
    w.header().min = {1, 2, 3};
    w.header().max = {4, 5, 6};
    const auto r = w.finish({vlr("test", 2, std::string(1000, 'x'), true)});
    EXPECT_EQ(r.points, 1234u);
    EXPECT_EQ(r.chunks, 0u);
    EXPECT_EQ(r.bytes_written, fs::file_size(out("a.las")));

    auto file = io::File::open(out("a.las"));
    auto tile = dataset::read_tile(file);
    EXPECT_FALSE(tile.compressed());
    EXPECT_EQ(tile.header.point_count, 1234u);
    EXPECT_EQ(tile.header.legacy_point_count, 0u);  // format 7: only the 64-bit count
    EXPECT_EQ(tile.header.min, (std::array<double, 3>{1, 2, 3}));
    EXPECT_EQ(tile.header.max, (std::array<double, 3>{4, 5, 6}));
    ASSERT_EQ(tile.vlrs().size(), 1u);
    EXPECT_EQ(tile.vlrs()[0].user_id, "test");
    ASSERT_EQ(tile.evlrs().size(), 1u);
    EXPECT_EQ(las::vlr_payload(file, tile.evlrs()[0]).size(), 1000u);
    EXPECT_EQ(read_back(out("a.las")), recs);
}

TEST_F(LasWriter, LazChunksAndOwnLaszipRecord) {
    const auto recs = records(7, 2500);
    laz::LasWriterOptions opt;
    opt.chunk_size = 1000;
    // A LASzip VLR among the caller's records is replaced by the writer's own.
    laz::LasWriter w(out("a.laz"), header(7), {vlr("laszip encoded", 22204, "stale"), vlr("test", 1, "x")}, opt, pool);
    w.add(recs);
    const auto r = w.finish();
    EXPECT_EQ(r.points, 2500u);
    EXPECT_EQ(r.chunks, 3u);
    auto file = io::File::open(out("a.laz"));
    auto tile = dataset::read_tile(file);
    ASSERT_TRUE(tile.compressed());
    EXPECT_EQ(tile.laz()->compressor, 3);
    EXPECT_EQ(tile.laz()->chunk_size, 1000u);
    EXPECT_EQ(tile.vlrs().size(), 2u);
    EXPECT_EQ(tile.chunks()->size(), 3u);
    EXPECT_EQ(read_back(out("a.laz")), recs);
}

TEST_F(LasWriter, SameBytesWhateverTheBatches) {
    const auto recs = records(3, 5000);
    const auto size = las::point_format_info(3).size;
    laz::LasWriterOptions opt;
    opt.chunk_size = 1200;
    las::Header h = header(3);
    h.version_minor = 2;
    h.header_size = las::standard_header_size(1, 2);
    {
        laz::LasWriter w(out("one.laz"), h, {}, opt, pool);
        w.add(recs);
        w.finish();
    }
    {
        ThreadPool single(1);
        laz::LasWriter w(out("many.laz"), h, {}, opt, single);
        for (std::size_t at = 0, step = 1; at < 5000; at += step, step = step * 3 % 1777 + 1) {
            const std::size_t n = std::min<std::size_t>(step, 5000 - at);
            w.add(std::span(recs).subspan(at * size, n * size));
        }
        w.finish();
    }
    EXPECT_EQ(bytes(out("one.laz")), bytes(out("many.laz")));
    EXPECT_EQ(read_back(out("one.laz")), recs);
}

TEST_F(LasWriter, UnfinishedFileNeverAppears) {
    {
        laz::LasWriter w(out("gone.laz"), header(7), {}, {}, pool);
        w.add(records(7, 10));
        EXPECT_THROW(w.add(std::vector<std::uint8_t>(5)), Error);  // a partial record
    }
    EXPECT_FALSE(fs::exists(out("gone.laz")));
    for (const auto& e : fs::directory_iterator(dir)) ADD_FAILURE() << "left behind: " << e.path();
}

TEST_F(LasWriter, RejectsZeroChunkSize) {
    laz::LasWriterOptions opt;
    opt.chunk_size = 0;
    EXPECT_THROW(laz::LasWriter(out("x.laz"), header(7), {}, opt, pool), Error);
}

}  // namespace
}  // namespace lidarscout
