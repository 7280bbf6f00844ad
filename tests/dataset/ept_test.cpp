// dataset/ept: an EPT dataset's LAZ nodes are its tiles, from the hierarchy (sub-hierarchy
// files followed, empty nodes left out), for local paths and URLs alike; other data types
// are an error. Hostile hierarchies end bounded: a DAG is read one file at a time, nodes and
// bytes are limited, and keys that are not node keys (URLs of other origins, absolute paths)
// are refused before anything is read from them.
#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <thread>

#include <nlohmann/json.hpp>

#include "dataset/ept.hpp"
#include "dataset/file_search.hpp"
#include "net/fault_server.hpp"
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

class EptHostile : public ::testing::Test {
protected:
    fs::path dir = fs::temp_directory_path() / ("lidarscout_ept_hostile_" + std::to_string(::getpid()));
    void SetUp() override { fs::create_directories(dir / "ept-hierarchy"); }
    void TearDown() override { fs::remove_all(dir); }

    void write(const fs::path& relative, const std::string& text) const { std::ofstream(dir / relative) << text; }
    // A hierarchy of `layers` layers of two files each, both files of every layer naming both
    // of the next: 2^layers paths through it, 2 * layers + 1 files.
    void write_dag(int layers) const {
        write("ept.json", R"({"dataType": "laszip"})");
        auto next = [](int depth) {
            const std::string d = std::to_string(depth);
            return "\"" + d + "-0-0-0\": -1, \"" + d + "-1-0-0\": -1";
        };
        write("ept-hierarchy/0-0-0-0.json", "{\"0-0-0-0\": 1, " + next(1) + "}");
        for (int depth = 1; depth <= layers; ++depth) {
            for (const int x : {0, 1}) {
                const std::string key = std::to_string(depth) + "-" + std::to_string(x) + "-0-0";
                write("ept-hierarchy/" + key + ".json",
                      "{\"" + key + "\": 1" + (depth < layers ? ", " + next(depth + 1) : std::string()) + "}");
            }
        }
    }
};

// 40 layers: 2^40 paths, each file read once (the depth-first reader of before never ended).
TEST_F(EptHostile, DagHierarchyIsReadOneFileAtATime) {
    write_dag(40);
    const auto nodes = ept_nodes((dir / "ept.json").string());
    EXPECT_TRUE(nodes.errors.empty()) << nodes.errors[0];
    EXPECT_EQ(nodes.hierarchy_files, 81u);
    EXPECT_EQ(nodes.tiles.size(), 81u);
}

TEST_F(EptHostile, NodesAndHierarchyBytesAreBounded) {
    write_dag(10);
    const auto by_nodes = ept_nodes((dir / "ept.json").string(), {.max_nodes = 20});
    EXPECT_TRUE(by_nodes.tiles.empty());
    ASSERT_EQ(by_nodes.errors.size(), 1u);
    EXPECT_NE(by_nodes.errors[0].find("more than the limit of 20 nodes"), std::string::npos) << by_nodes.errors[0];
    EXPECT_LE(by_nodes.hierarchy_files, 10u);
    const auto by_bytes = ept_nodes((dir / "ept.json").string(), {.max_hierarchy_bytes = 300});
    EXPECT_TRUE(by_bytes.tiles.empty());
    ASSERT_EQ(by_bytes.errors.size(), 1u);
    EXPECT_NE(by_bytes.errors[0].find("larger than the limit of 300 bytes"), std::string::npos) << by_bytes.errors[0];
    EXPECT_LE(by_bytes.hierarchy_files, 10u);
}

// Keys naming other hosts, absolute paths or folders above the dataset: refused, nothing read.
TEST_F(EptHostile, KeysThatAreNotNodeKeysAreRefusedLocally) {
    test::FaultServer other({1, 2, 3});
    const std::string elsewhere = other.url().substr(0, other.url().find('/', 7));
    write("entwine.json", R"({"dataType": "laszip"})");
    fs::create_directories(dir / "h");
    for (const std::string& key : std::vector<std::string>{elsewhere + "/x", "//127.0.0.1/x", (dir / "secret").string(),
                                                          "../../up", "1-2-0-0", "65-0-0-0", "0-0-0"}) {
        SCOPED_TRACE(key);
        write("h/0-0-0-0.json", nlohmann::json({{"0-0-0-0", 1}, {key, 5}}).dump());
        const auto nodes = ept_nodes((dir / "entwine.json").string());
        EXPECT_TRUE(nodes.tiles.empty());
        ASSERT_EQ(nodes.errors.size(), 1u);
        EXPECT_NE(nodes.errors[0].find("is not a node key D-X-Y-Z"), std::string::npos) << nodes.errors[0];
    }
    EXPECT_EQ(other.requests(), 0);
}

// The same DAG served by nginx: each hierarchy file is fetched once (one request each, as
// files of less than 4 KiB are read whole by the request that opens them).
TEST_F(EptHostile, RemoteDagHierarchyFetchesEachFileOnce) {
    const auto& server = test::NginxServer::instance();
    write_dag(20);
    const fs::path set = server.lists_dir() / "dag-ept";
    fs::remove_all(set);
    fs::copy(dir, set, fs::copy_options::recursive);
    // Requests for this dataset only (other tests share the server and its log).
    auto logged = [&] {
        std::ifstream in(server.access_log());
        std::string line;
        long n = 0;
        while (std::getline(in, line)) n += line.find("/lists/dag-ept/") != std::string::npos;
        return n;
    };
    const auto before = logged();
    const auto nodes = ept_nodes(server.url("lists/dag-ept/ept.json"));
    EXPECT_TRUE(nodes.errors.empty()) << nodes.errors[0];
    EXPECT_EQ(nodes.tiles.size(), 41u);
    EXPECT_EQ(nodes.hierarchy_files, 41u);
    // nginx logs a request after its response is sent: wait for the lines to come (bounded).
    for (int i = 0; i < 500 && logged() - before < 42; ++i) std::this_thread::sleep_for(std::chrono::milliseconds(10));
    EXPECT_EQ(logged() - before, 42);  // ept.json and the 41 hierarchy files
    fs::remove_all(set);
}

// A remote Entwine dataset whose keys name another origin, or plain http from an https
// dataset: refused, and no request reaches the other origin.
TEST(EptRemote, KeysCannotLeaveTheDatasetsOrigin) {
    const auto& server = test::NginxServer::instance();
    test::FaultServer other({1, 2, 3});
    const std::string host = other.url().substr(7, other.url().find('/', 7) - 7);
    const fs::path set = server.lists_dir() / "hostile-entwine";
    fs::create_directories(set / "h");
    std::ofstream(set / "entwine.json") << R"({"dataType": "laszip"})";
    for (const std::string& key : std::vector<std::string>{"http://" + host + "/x", "//" + host + "/x",
                                                           "https://" + host + "/x"}) {
        SCOPED_TRACE(key);
        std::ofstream(set / "h" / "0-0-0-0.json") << nlohmann::json({{"0-0-0-0", 1}, {key, -1}}).dump();
        const auto found = find_point_cloud_files({server.url("lists/hostile-entwine/entwine.json")});
        EXPECT_TRUE(found.files.empty());
        ASSERT_EQ(found.errors.size(), 1u);
        EXPECT_NE(found.errors[0].error.find("is not a node key"), std::string::npos) << found.errors[0].error;
    }
    EXPECT_EQ(other.requests(), 0);
    fs::remove_all(set);
}

}  // namespace
}  // namespace lidarscout::dataset
