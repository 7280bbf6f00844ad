// `lidarscout catalog` as a user runs it: a folder written as a .vpc that `info` and `clip` then
// open as the same tiles; an s3:// prefix written as a .vpc of s3:// hrefs that opens again;
// an output that is not a .vpc, or named like an input, refused with nothing written.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include <nlohmann/json.hpp>

#include "s3_server.hpp"
#include "temp_dir_fixture.hpp"
#include "test_data.hpp"

namespace lidarscout {
namespace {

namespace fs = std::filesystem;

class CatalogCommand : public test::TempDirTest {
protected:
    static std::string cli() { return std::string(LIDARSCOUT_CLI) + " "; }
    static std::string ign() { return (test::surveys_dir() / "ign-lidar-hd-1km").string(); }
};

TEST_F(CatalogCommand, AFolderBecomesACatalogOtherCommandsOpen) {
    std::string out;
    ASSERT_EQ(test::run_command(cli() + "catalog " + ign() + " -o " + path("ign.vpc") + " --json 2>/dev/null", out), 0)
        << out;
    const auto j = nlohmann::json::parse(out);
    EXPECT_EQ(j.at("items"), 7);
    EXPECT_EQ(j.at("points"), 1'300'376);
    ASSERT_EQ(test::run_command(cli() + "info " + path("ign.vpc") + " 2>&1", out), 0) << out;
    EXPECT_NE(out.find("dataset: 7 files (0 failed), 1,300,376 points"), std::string::npos) << out;
    EXPECT_EQ(out.find("disagrees"), std::string::npos) << out;
}

TEST_F(CatalogCommand, AnS3PrefixBecomesACatalogOfS3Hrefs) {
    auto& server = test::S3Server::instance();
    for (const auto& entry : fs::directory_iterator(ign())) {
        if (entry.path().extension() != ".laz") continue;
        server.put_file("tiles", "ign/" + entry.path().filename().string(), entry);
    }
    const std::string env = "AWS_SHARED_CREDENTIALS_FILE=/dev/null AWS_ENDPOINT_URL=" + server.endpoint() +
                            " AWS_ACCESS_KEY_ID=" + test::S3Server::kKey + " AWS_SECRET_ACCESS_KEY=" +
                            test::S3Server::kSecret + " ";
    std::string out;
    ASSERT_EQ(test::run_command(env + cli() + "catalog s3://tiles/ign/ -o " + path("ign.vpc") + " --json 2>&1", out), 0)
        << out;
    EXPECT_EQ(nlohmann::json::parse(out).at("items"), 7);
    const auto vpc = nlohmann::json::parse(std::ifstream(path("ign.vpc")));
    const auto href = vpc.at("features").at(0).at("assets").at("data").at("href").get<std::string>();
    EXPECT_EQ(href.rfind("s3://tiles/ign/", 0), 0u) << href;
    ASSERT_EQ(test::run_command(env + cli() + "info " + path("ign.vpc") + " 2>&1", out), 0) << out;
    EXPECT_NE(out.find("dataset: 7 files (0 failed), 1,300,376 points"), std::string::npos) << out;
}

TEST_F(CatalogCommand, AnOutputThatIsNotAVpcOrIsAnInputIsRefused) {
    std::string out;
    EXPECT_EQ(test::run_command(cli() + "catalog " + ign() + " -o " + path("ign.laz") + " 2>&1", out), 1) << out;
    EXPECT_NE(out.find(".vpc"), std::string::npos) << out;
    EXPECT_FALSE(fs::exists(path("ign.laz")));
    ASSERT_EQ(test::run_command(cli() + "catalog " + ign() + " -o " + path("ign.vpc") + " 2>&1", out), 0) << out;
    const auto before = fs::file_size(path("ign.vpc"));
    EXPECT_EQ(test::run_command(cli() + "catalog " + path("ign.vpc") + " -o " + path("ign.vpc") + " 2>&1", out), 1)
        << out;
    EXPECT_EQ(fs::file_size(path("ign.vpc")), before) << "the input catalog is left as it was";
}

}  // namespace
}  // namespace lidarscout
