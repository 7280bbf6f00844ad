// `lidarscout convert`: converts by the output's extension, reports bad arguments in one line.
#include <gtest/gtest.h>

#include <unistd.h>

#include "test_data.hpp"

namespace lidarscout {
namespace {

namespace fs = std::filesystem;

TEST(ConvertCommand, LasToLazAndBack) {
    const auto dir = fs::temp_directory_path() / ("lidarscout_convert_cli_" + std::to_string(::getpid()));
    fs::create_directories(dir);
    const auto in = (test::formats_dir() / "laz-rs__laz-rs/tests__data__point-time-color.las").string();
    std::string out;
    ASSERT_EQ(test::run_command(
                  std::string(LIDARSCOUT_CLI) + " convert " + in + " " + (dir / "a.laz").string() + " --json", out),
              0);
    auto j = nlohmann::json::parse(out);
    EXPECT_EQ(j.at("points"), 1065);
    EXPECT_EQ(j.at("chunks"), 1);
    ASSERT_EQ(
        test::run_command(std::string(LIDARSCOUT_CLI) + " info --checksum --json " + (dir / "a.laz").string(), out), 0);
    const auto want =
        test::read_json(test::formats_dir() / "expected/laz-rs__laz-rs__tests__data__point-time-color.las.json");
    EXPECT_EQ(nlohmann::json::parse(out).at(0).at("points_sha256"), want.at("points_sha256"));
    fs::remove_all(dir);
}

TEST(ConvertCommand, RejectsUnknownExtensionAndSamePath) {
    const auto in = (test::formats_dir() / "laz-rs__laz-rs/tests__data__point-time-color.las").string();
    std::string out;
    EXPECT_EQ(test::run_command(std::string(LIDARSCOUT_CLI) + " convert " + in + " /tmp/x.txt 2>&1", out), 1);
    EXPECT_NE(out.find("it must end in one of .las, .laz (.txt given)"), std::string::npos) << out;
    EXPECT_EQ(test::run_command(std::string(LIDARSCOUT_CLI) + " convert " + in + " " + in + " 2>&1", out), 1);
    EXPECT_NE(out.find("refusing the output of OUTPUT: it is the input"), std::string::npos) << out;
    EXPECT_EQ(test::run_command(std::string(LIDARSCOUT_CLI) + " convert --help", out), 0);
    EXPECT_NE(out.find("--chunk-size"), std::string::npos);
}

}  // namespace
}  // namespace lidarscout
