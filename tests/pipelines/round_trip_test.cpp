// Round trips through our encoder are lossless: every LAS file of the corpus (formats 0-10, wave
// packets included) LAS->LAZ->LAS, and every survey tile LAZ->LAZ (re-encoded from decoded
// records), give the same SHA-256 over their point records as the original.
#include <gtest/gtest.h>

#include <unistd.h>

#include "core/sha256.hpp"
#include "core/thread_pool.hpp"
#include "dataset/file_search.hpp"
#include "dataset/point_reader.hpp"
#include "dataset/tile.hpp"
#include "pipelines/tile_writer.hpp"
#include "io/file.hpp"
#include "las/header.hpp"
#include "las/point_format.hpp"
#include "test_data.hpp"

namespace lidarscout {
namespace {

namespace fs = std::filesystem;

ThreadPool& pool() {
    static ThreadPool p(2);
    return p;
}

std::string checksum(const std::string& path) {
    auto file = io::File::open(path);
    auto tile = dataset::read_tile(file);
    Sha256 sha;
    dataset::for_each_record_batch(file, tile, pool(),
                                   [&](std::uint64_t, std::span<const std::uint8_t> r) { sha.update(r); });
    return sha.hex_digest();
}

class RoundTrip : public ::testing::TestWithParam<std::string> {
protected:
    fs::path dir = fs::temp_directory_path() / ("lidarscout_rt_" + std::to_string(::getpid()));
    void SetUp() override { fs::create_directories(dir); }
    void TearDown() override { fs::remove_all(dir); }
};

TEST_P(RoundTrip, Lossless) {
    const std::string in = GetParam();
    const auto laz = (dir / "a.laz").string();
    const auto las = (dir / "b.las").string();
    pipelines::ConvertOptions opt;
    pipelines::convert_tile(in, laz, opt, pool());
    opt.compress = false;
    pipelines::convert_tile(laz, las, opt, pool());
    const auto want = checksum(in);
    EXPECT_EQ(checksum(laz), want);
    EXPECT_EQ(checksum(las), want);
}

// Readable LAS files of the corpus (the encoder writes every point format), but those with wave packets
// and waveform data inside the file, which convert refuses (laspy's simple1_3.las).
std::vector<std::string> corpus_las_files() {
    std::vector<std::string> out;
    for (const auto& [name, ok] : test::index_outcomes()) {
        const auto path = (test::formats_dir() / name).string();
        if (!ok || fs::path(name).extension() != ".las") continue;
        const auto h = las::read_header(io::File::open(path));  // (no CRS asked of PROJ: every process lists these)
        if (las::point_format_info(h.point_format).wave_offset < 0 || !(h.global_encoding & 2)) out.push_back(path);
    }
    return out;
}

std::vector<std::string> survey_tiles() {
    return dataset::find_point_cloud_files({test::surveys_dir().string()}).files;
}

std::string name_of(const ::testing::TestParamInfo<std::string>& info) {
    auto s = fs::relative(info.param, test::data_dir()).string();
    for (char& c : s) if (!std::isalnum(static_cast<unsigned char>(c))) c = '_';
    return s;
}

INSTANTIATE_TEST_SUITE_P(CorpusLas, RoundTrip, ::testing::ValuesIn(corpus_las_files()), name_of);
INSTANTIATE_TEST_SUITE_P(Surveys, RoundTrip, ::testing::ValuesIn(survey_tiles()), name_of);

TEST(RoundTripCoverage, CorpusAndSurveys) {
    EXPECT_GT(corpus_las_files().size(), 40u);
    EXPECT_EQ(survey_tiles().size(), 107u);
}

}  // namespace
}  // namespace lidarscout
