// dataset/ept: an EPT dataset's LAZ nodes are its tiles, from the hierarchy (sub-hierarchy
// files followed, empty nodes left out), for local paths and URLs alike; other data types
// are an error.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>

#include "dataset/ept.hpp"
#include "dataset/file_search.hpp"
#include "nginx_server.hpp"
#include "test_data.hpp"

namespace lidarscout::dataset {
namespace {

namespace fs = std::filesystem;

const char* const kEntwine = "surveys/nc-raleigh-ept/ept/entwine.json";

TEST(Ept, EntwineNodesAreTheFolderTiles) {
    const auto nodes = ept_nodes((test::data_dir() / kEntwine).string());
    EXPECT_TRUE(nodes.errors.empty());
    ASSERT_EQ(nodes.tiles.size(), 77u);
    EXPECT_EQ(fs::path(nodes.tiles.front()).filename(), "0-0-0-0.laz");
    auto folder = find_point_cloud_files({(test::data_dir() / "surveys/nc-raleigh-ept/ept").string()}).files;
    auto listed = nodes.tiles;
    std::sort(listed.begin(), listed.end());
    EXPECT_EQ(listed, folder);
}

TEST(Ept, RemoteMetadataGivesNodeUrls) {
    const auto& server = test::NginxServer::instance();
    const auto found = find_point_cloud_files({server.url(kEntwine)});
    EXPECT_TRUE(found.errors.empty());
    ASSERT_EQ(found.files.size(), 77u);
    EXPECT_EQ(found.files.front(), server.url("surveys/nc-raleigh-ept/ept/0-0-0-0.laz"));
}

TEST(Ept, SubHierarchiesAreFollowedAndEmptyNodesLeftOut) {
    const fs::path dir = fs::temp_directory_path() / ("lidarscout_ept_" + std::to_string(::getpid()));
    fs::create_directories(dir / "ept-hierarchy");
    std::ofstream(dir / "ept.json") << R"({"dataType": "laszip", "hierarchyType": "json"})";
    std::ofstream(dir / "ept-hierarchy" / "0-0-0-0.json") << R"({"0-0-0-0": 5, "1-0-0-0": -1, "1-1-0-0": 0})";
    std::ofstream(dir / "ept-hierarchy" / "1-0-0-0.json") << R"({"1-0-0-0": 3, "2-0-0-1": 2, "2-0-0-0": 1})";
    const auto nodes = ept_nodes((dir / "ept.json").string());
    EXPECT_TRUE(nodes.errors.empty());
    std::vector<std::string> names;
    for (const auto& t : nodes.tiles) names.push_back(fs::relative(t, dir).string());
    EXPECT_EQ(names, (std::vector<std::string>{"ept-data/0-0-0-0.laz", "ept-data/1-0-0-0.laz", "ept-data/2-0-0-0.laz",
                                               "ept-data/2-0-0-1.laz"}));

    std::ofstream(dir / "ept.json") << R"({"dataType": "binary"})";
    const auto binary = ept_nodes((dir / "ept.json").string());
    EXPECT_TRUE(binary.tiles.empty());
    ASSERT_EQ(binary.errors.size(), 1u);
    EXPECT_NE(binary.errors[0].find("\"binary\" is not supported"), std::string::npos) << binary.errors[0];
    fs::remove_all(dir);
}

}  // namespace
}  // namespace lidarscout::dataset
