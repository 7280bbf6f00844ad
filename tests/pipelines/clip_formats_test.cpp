// pipelines::clip_to_file over every format it can read: every formats/ file that decodes (INDEX.md)
// and has points, clipped by a box around everything to .las and to .laz, reads back through our
// reader with the input's point count, point format, version and records (SHA-256 in file order); a
// LAS 1.5 input keeps its 393-byte header, with the kept points' GPS time range. What the output cannot
// hold is refused naming the file and the fix, nothing written (no output, no temporary), and with
// force dropped: waveform data (laspy's simple1_3.las has 100 bytes inside the file; rlas's fwf.laz and
// laspy's fullwave.laz an external .wdp file), the records then coming back with their wave packets'
// descriptor index, offset and size 0 and nothing else changed; a CRS in user-defined GeoTIFF keys
// that formats 6-10 need as WKT (two TerraScan files), its keys then kept.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <set>
#include <string>
#include <vector>

#include "core/error.hpp"
#include "core/sha256.hpp"
#include "core/thread_pool.hpp"
#include "dataset/dataset.hpp"
#include "dataset/point_reader.hpp"
#include "io/file.hpp"
#include "las/header.hpp"
#include "las/point_format.hpp"
#include "pipelines/clip.hpp"
#include "temp_dir_fixture.hpp"
#include "test_data.hpp"

namespace lidarscout::pipelines {
namespace {

namespace fs = std::filesystem;

// A tile's records in file order, all of them, as our reader gives them.
std::vector<std::uint8_t> records_of(const std::string& path) {
    const auto file = io::File::open(path);
    const auto tile = dataset::read_tile(file);
    std::vector<std::uint8_t> out;
    out.reserve(tile.header.point_count * tile.header.record_length);
    dataset::for_each_record_batch(file, tile, ThreadPool::shared(),
                                   [&](std::uint64_t, std::span<const std::uint8_t> r) {
                                       out.insert(out.end(), r.begin(), r.end());
                                   });
    return out;
}

std::string sha(std::span<const std::uint8_t> bytes) {
    Sha256 s;
    s.update(bytes);
    return s.hex_digest();
}

dataset::Dataset open_one(const std::string& path) {
    dataset::DatasetOptions options;
    options.accept_degrees = true;  // as clip opens its inputs
    return dataset::open_dataset({path}, options);
}

// Clips all of `ds` (a box around every point the doubles can hold) into `output`.
ClipResult clip_all(const dataset::Dataset& ds, const std::string& output, bool force = false) {
    constexpr double kFar = std::numeric_limits<double>::max();
    ClipRequest request;
    request.output = output;
    request.region = box_region(-kFar, -kFar, kFar, kFar);
    request.force = force;
    return clip_to_file(ds, request, ThreadPool::shared());
}

// The files of formats/ that decode and hold points.
std::vector<std::string> decoding_files() {
    std::vector<std::string> out;
    for (const auto& [name, ok] : test::index_outcomes()) {
        if (!ok) continue;
        const auto path = (test::formats_dir() / name).string();
        if (las::read_header(io::File::open(path)).point_count > 0) out.push_back(path);  // (no CRS asked of PROJ)
    }
    return out;
}

std::string name_of(const ::testing::TestParamInfo<std::string>& info) {
    auto s = fs::relative(info.param, test::formats_dir()).string();
    for (char& c : s) if (!std::isalnum(static_cast<unsigned char>(c))) c = '_';
    return s;
}

// The inputs whose CRS (user-defined GeoTIFF keys, formats 6-10) a clip can keep only when forced.
bool crs_needs_force(const std::string& path) {
    return path.ends_with("SDFIdk__DHMQC/demo__1km_6076_548.laz") ||
           path.ends_with("IGNF__ign-pdal-tools/test__data__test_pdalfail_0643_6319_LA93_IGN69.laz");
}

bool has_waveform_data(const las::Header& h) {
    return las::point_format_info(h.point_format).wave_offset >= 0 && ((h.global_encoding & 6) || h.waveform_offset);
}

// The records with every wave packet's descriptor index, data offset and size set to 0.
std::vector<std::uint8_t> without_waveform_references(std::vector<std::uint8_t> records, const las::Header& h) {
    const int at = las::point_format_info(h.point_format).wave_offset;
    for (std::size_t r = 0; r < records.size(); r += h.record_length) std::memset(&records[r + at], 0, 13);
    return records;
}

// The GPS time range of records of format `h.point_format` (0, 0 without GPS time).
std::pair<double, double> gps_range(std::span<const std::uint8_t> records, const las::Header& h) {
    const int at = las::point_format_info(h.point_format).gps_offset;
    if (at < 0) return {0.0, 0.0};
    double lo = INFINITY, hi = -INFINITY;
    for (std::size_t r = 0; r < records.size(); r += h.record_length) {
        double t = 0;
        std::memcpy(&t, &records[r + at], 8);
        lo = std::min(lo, t), hi = std::max(hi, t);
    }
    return {lo, hi};
}

// The message of a refused clip into `output`, after checking that nothing was written into `dir`
// ("" when it was not refused).
std::string refusal(const dataset::Dataset& ds, const std::string& output, const fs::path& dir) {
    try {
        clip_all(ds, output);
    } catch (const Error& e) {
        EXPECT_TRUE(fs::is_empty(dir)) << "written: " << fs::directory_iterator(dir)->path();
        return e.what();
    }
    return "";
}

class ClipEveryFormat : public test::TempDirTest, public ::testing::WithParamInterface<std::string> {};

// Refused or not (then forced), the output holds the input's records, but for the waveform data.
TEST_P(ClipEveryFormat, LasAndLazHoldTheInputsRecords) {
    const std::string input = GetParam();
    const auto ds = open_one(input);
    ASSERT_EQ(ds.tiles.size(), 1u) << (ds.skipped.empty() ? "" : ds.skipped[0].error);
    const las::Header& in = ds.tiles[0].tile.header;
    const auto want = records_of(input);
    const auto expected = has_waveform_data(in) ? without_waveform_references(want, in) : want;
    for (const char* name : {"clip.las", "clip.laz"}) {
        SCOPED_TRACE(name);
        ClipResult r;
        std::string refused;
        try {
            r = clip_all(ds, path(name));
        } catch (const Error& e) {
            refused = e.what();
            EXPECT_TRUE(fs::is_empty(dir)) << "written: " << fs::directory_iterator(dir)->path();
            EXPECT_EQ(refused.rfind(input + ": ", 0), 0u) << refused;
            EXPECT_NE(refused.find("; nothing written (--force "), std::string::npos) << refused;
            r = clip_all(ds, path(name), true);
        }
        EXPECT_EQ(!refused.empty(), has_waveform_data(in) || crs_needs_force(input)) << refused;
        EXPECT_EQ(r.points_written, in.point_count);
        const auto out = dataset::read_tile(io::File::open(path(name))).header;
        EXPECT_EQ(out.point_count, in.point_count);
        EXPECT_EQ(out.point_format, in.point_format);
        EXPECT_EQ(out.record_length, in.record_length);
        EXPECT_EQ(out.version_string(), in.version_string());
        EXPECT_EQ(out.compressed, std::string(name) == "clip.laz");
        EXPECT_EQ(out.global_encoding & 6, 0) << "waveform data is never carried";
        EXPECT_EQ(out.waveform_offset, 0u);
        const auto got = records_of(path(name));
        EXPECT_EQ(got.size(), expected.size());
        EXPECT_EQ(sha(got), sha(expected));
        if (in.at_least(1, 5)) {
            EXPECT_EQ(out.header_size, 393u);
            const auto [lo, hi] = gps_range(want, in);
            EXPECT_EQ(out.min_gps_time, lo);
            EXPECT_EQ(out.max_gps_time, hi);
        }
        fs::remove(path(name));
    }
}

INSTANTIATE_TEST_SUITE_P(Formats, ClipEveryFormat, ::testing::ValuesIn(decoding_files()), name_of);

TEST(ClipEveryFormatList, CoversEveryPointFormatAndLas15) {
    std::set<int> formats;
    std::size_t las15 = 0, waveforms = 0;
    for (const auto& path : decoding_files()) {
        const auto h = dataset::read_tile(io::File::open(path)).header;
        formats.insert(h.point_format);
        las15 += h.at_least(1, 5);
        waveforms += has_waveform_data(h);
    }
    EXPECT_EQ(formats.size(), 11u);
    EXPECT_EQ(las15, 4u);      // pdrf9 and pdrf10, LAS and LAZ
    EXPECT_EQ(waveforms, 3u);  // simple1_3.las, fwf.laz, fullwave.laz
}

class ClipRefusals : public test::TempDirTest {};

TEST_F(ClipRefusals, WaveformDataIsRefusedNamingWhereItIs) {
    const auto formats = test::formats_dir();
    const std::pair<fs::path, std::string> cases[] = {
        {formats / "laspy__laspy/tests__data__simple1_3.las",
         "waveform data packets inside the file (from byte 62728)"},
        {formats / "cran__rlas/inst__extdata__fwf.laz",
         "waveform data packets in an external file (" + (formats / "cran__rlas/inst__extdata__fwf.wdp").string()},
        {formats / "laspy__laspy/tests__data__fullwave.laz",
         "waveform data packets in an external file (" + (formats / "laspy__laspy/tests__data__fullwave.wdp").string()},
    };
    for (const auto& [input, where] : cases) {
        const auto ds = open_one(input.string());
        ASSERT_EQ(ds.tiles.size(), 1u);
        for (const char* name : {"w.las", "w.laz"}) {
            const std::string message = refusal(ds, path(name), dir);
            EXPECT_EQ(message.rfind(input.string() + ": " + where, 0), 0u) << message;
            EXPECT_NE(message.find("clip cannot carry them into " + path(name)), std::string::npos) << message;
            EXPECT_NE(message.find("nothing written (--force writes its points' wave packets without waveform "
                                   "data: descriptor index, offset and size 0)"),
                      std::string::npos)
                << message;
            EXPECT_EQ(std::count(message.begin(), message.end(), '\n'), 0) << message;
        }
    }
}

TEST_F(ClipRefusals, ForcedWavePacketsPointAtNoWaveformData) {
    const std::string input = (test::formats_dir() / "laspy__laspy/tests__data__simple1_3.las").string();
    const auto ds = open_one(input);
    const ClipResult r = clip_all(ds, path("w.laz"), true);
    ASSERT_EQ(r.notes.size(), 1u);
    EXPECT_EQ(r.notes[0], "waveform data dropped (1 of the 1 tiles touched have it; " + input +
                              ": waveform data packets inside the file (from byte 62728)): the wave packets written "
                              "have descriptor index, offset and size 0");
    const auto got = records_of(path("w.laz"));
    EXPECT_EQ(got, without_waveform_references(records_of(input), ds.tiles[0].tile.header));
    EXPECT_NE(got, records_of(input)) << "the descriptor index was 1 in every record";
}

TEST_F(ClipRefusals, ACrsFormats6To10CannotStateIsRefusedOrItsKeysKept) {
    const std::string input = (test::formats_dir() / "SDFIdk__DHMQC/demo__1km_6076_548.laz").string();
    const auto ds = open_one(input);
    const std::string message = refusal(ds, path("c.las"), dir);
    EXPECT_EQ(message.rfind(input + ": point format 6 needs the CRS as WKT: ", 0), 0u) << message;
    EXPECT_NE(message.find("; nothing written (--force keeps the GeoTIFF keys)"), std::string::npos) << message;
    const ClipResult r = clip_all(ds, path("c.las"), true);
    ASSERT_EQ(r.notes.size(), 1u);
    EXPECT_NE(r.notes[0].find("needs the CRS as WKT"), std::string::npos) << r.notes[0];
    EXPECT_NE(r.notes[0].find("; the GeoTIFF keys kept"), std::string::npos) << r.notes[0];
    const auto out = dataset::read_tile(io::File::open(path("c.las")));
    EXPECT_TRUE(std::any_of(out.vlrs().begin(), out.vlrs().end(),
                            [](const las::Vlr& v) { return v.is("LASF_Projection", 34735); }));
}

}  // namespace
}  // namespace lidarscout::pipelines
