// AtomicOutputFile: the target appears only on commit, is never the protected input, and
// copy_from appends an exact byte range of another file.
#include <gtest/gtest.h>

#include <unistd.h>

#include <fstream>
#include <iterator>

#include "core/error.hpp"
#include "io/file.hpp"
#include "io/output_file.hpp"
#include "test_data.hpp"

namespace lidarscout {
namespace {

namespace fs = std::filesystem;

struct TempDir {
    fs::path path = fs::temp_directory_path() / ("lidarscout_output_file_" + std::to_string(::getpid()));
    TempDir() {
        fs::remove_all(path);
        fs::create_directories(path);
    }
    ~TempDir() { fs::remove_all(path); }
};

std::vector<std::uint8_t> slurp(const fs::path& p) {
    std::ifstream in(p, std::ios::binary);
    return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

TEST(OutputFile, AppearsOnlyOnCommit) {
    TempDir dir;
    const auto target = dir.path / "a.bin";
    {
        io::AtomicOutputFile out(target.string());
        const std::uint8_t bytes[] = {1, 2, 3, 4};
        out.write(bytes);
        const std::uint8_t patch[] = {9};
        out.write_at(1, patch);
        EXPECT_EQ(out.size(), 4u);
        EXPECT_FALSE(fs::exists(target));
        out.commit();
    }
    EXPECT_EQ(slurp(target), (std::vector<std::uint8_t>{1, 9, 3, 4}));
    {
        io::AtomicOutputFile out((dir.path / "b.bin").string());
        const std::uint8_t bytes[] = {1};
        out.write(bytes);
    }
    EXPECT_FALSE(fs::exists(dir.path / "b.bin"));
    EXPECT_EQ(std::distance(fs::directory_iterator(dir.path), fs::directory_iterator()), 1) << "no temporary left";
}

// A writer that checks the name it writes (GDAL's GeoPackage driver warned "The filename extension
// should be 'gpkg' instead of 'tmp-NNNN'") sees the target's extension on the temporary file.
TEST(OutputFile, TemporaryNameKeepsTheExtension) {
    TempDir dir;
    const io::AtomicOutputFile gpkg((dir.path / "c_contours.gpkg").string());
    const std::string pid = std::to_string(::getpid());
    EXPECT_EQ(fs::path(gpkg.temp_path()), dir.path / (".c_contours.gpkg.tmp-" + pid + ".gpkg"));
    const io::AtomicOutputFile bare((dir.path / "noext").string());
    EXPECT_EQ(fs::path(bare.temp_path()), dir.path / (".noext.tmp-" + pid));
}

TEST(OutputFile, RefusesToOverwriteTheInput) {
    TempDir dir;
    const auto input = (dir.path / "in.bin").string();
    std::ofstream(input) << "data";
    EXPECT_THROW(io::AtomicOutputFile(input, input), Error);
    EXPECT_EQ(slurp(input).size(), 4u);
}

TEST(OutputFile, CopyFromAppendsAnExactRange) {
    TempDir dir;
    const auto source_path = test::surveys_dir() / "ign-lidar-hd-1km/Semis_2022_0906_6665_LA93_IGN69_ok.laz";
    const auto source = io::File::open(source_path.string());
    const auto want = slurp(source_path);
    const auto target = dir.path / "copy.bin";
    {
        io::AtomicOutputFile out(target.string());
        const std::uint8_t head[] = {7, 7};
        out.write(head);
        out.copy_from(source, 100, 5000);
        out.copy_from(source, 0, source.size());
        out.copy_from(source, 0, 0);
        EXPECT_EQ(out.size(), 2u + 5000u + source.size());
        out.commit();
    }
    const auto got = slurp(target);
    ASSERT_EQ(got.size(), 2u + 5000u + want.size());
    EXPECT_EQ(got[0], 7);
    EXPECT_TRUE(std::equal(want.begin() + 100, want.begin() + 5100, got.begin() + 2));
    EXPECT_TRUE(std::equal(want.begin(), want.end(), got.begin() + 5002));
}

// Across file systems (the data on disk, the target in tmpfs) the kernel may refuse
// copy_file_range (EXDEV); the plain read/write fallback must give the same bytes.
TEST(OutputFile, CopyFromAcrossFileSystems) {
    if (!fs::is_directory("/dev/shm")) GTEST_SKIP() << "no /dev/shm";
    const auto source_path = test::surveys_dir() / "ign-lidar-hd-1km/Semis_2022_0906_6665_LA93_IGN69_ok.laz";
    const auto source = io::File::open(source_path.string());
    const fs::path target = "/dev/shm/lidarscout_output_file_" + std::to_string(::getpid()) + ".bin";
    {
        io::AtomicOutputFile out(target.string());
        out.copy_from(source, 0, source.size());
        out.commit();
    }
    EXPECT_EQ(slurp(target), slurp(source_path));
    fs::remove(target);
}

TEST(OutputFile, CopyFromPastTheEndThrows) {
    TempDir dir;
    const auto source =
        io::File::open((test::surveys_dir() / "ign-lidar-hd-1km/Semis_2022_0906_6665_LA93_IGN69_ok.laz").string());
    io::AtomicOutputFile out((dir.path / "x.bin").string());
    try {
        out.copy_from(source, source.size() - 10, 20);
        FAIL() << "no error";
    } catch (const Error& e) {
        EXPECT_EQ(e.file(), source.path());
        EXPECT_NE(std::string(e.what()).find("ends before"), std::string::npos) << e.what();
    }
}

}  // namespace
}  // namespace lidarscout
