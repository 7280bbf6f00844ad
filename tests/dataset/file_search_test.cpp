// dataset/file_search with URLs: a remote tile list's relative entries resolve against its
// URL, a local list may name URLs, a URL to a LAS/LAZ file is a tile, and a list that
// cannot be fetched is reported; the local inputs behind lists and manifests.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "dataset/file_search.hpp"
#include "nginx_server.hpp"
#include "synth/replicate.hpp"
#include "test_data.hpp"

namespace lidarscout::dataset {
namespace {

namespace fs = std::filesystem;

TEST(FileSearch, RemoteListEntriesResolveAgainstTheListUrl) {
    const auto& server = test::NginxServer::instance();
    std::ofstream(server.lists_dir() / "relative.txt")
        << "# tiles\n../surveys/ky-woodford-county/5205000_3900000.laz\n\n  sub/a.laz  \n"
        << "http://example.invalid/b.laz\n";
    const auto found = find_point_cloud_files({server.url("lists/relative.txt")});
    EXPECT_TRUE(found.errors.empty());
    EXPECT_EQ(found.files, (std::vector<std::string>{server.url("surveys/ky-woodford-county/5205000_3900000.laz"),
                                                     server.url("lists/sub/a.laz"), "http://example.invalid/b.laz"}));
}

TEST(FileSearch, LocalListMayNameUrlsAndUrlsToTilesAreTiles) {
    const fs::path list = fs::temp_directory_path() / ("lidarscout_urls_" + std::to_string(::getpid()) + ".txt");
    std::ofstream(list) << "https://host/x.laz?sig=1\n";
    const auto found = find_point_cloud_files({list.string(), "http://host/y.LAS"});
    EXPECT_EQ(found.files, (std::vector<std::string>{"https://host/x.laz?sig=1", "http://host/y.LAS"}));
    fs::remove(list);
}

TEST(FileSearch, MissingRemoteListIsReported) {
    const auto found = find_point_cloud_files({test::NginxServer::instance().url("lists/none.txt")});
    EXPECT_TRUE(found.files.empty());
    ASSERT_EQ(found.errors.size(), 1u);
    EXPECT_NE(found.errors[0].error.find("404"), std::string::npos) << found.errors[0].error;
}

// local_inputs (for the output check): what a tile list and a virtual replica manifest name,
// without searching folders; URLs left out.
TEST(FileSearch, LocalInputsFollowTileListsAndVirtualReplicaManifests) {
    const fs::path dir = fs::temp_directory_path() / ("lidarscout_local_inputs_" + std::to_string(::getpid()));
    fs::create_directories(dir / "rep");
    const std::string tile = (test::surveys_dir() / "ign-lidar-hd-1km/Semis_2022_0906_6665_LA93_IGN69_ok.laz").string();
    std::ofstream(dir / "list.txt") << "# tiles\n" << tile << "\nsub\nhttp://example.invalid/b.laz\n";
    synth::write_virtual_replica(synth::plan_replicas({tile}, (dir / "rep").string(), {2, 1}));
    const std::string list = (dir / "list.txt").string(), manifest = (dir / "rep/replicate.json").string();
    EXPECT_EQ(local_inputs({list}), (std::vector<std::string>{list, tile, (dir / "sub").string()}));
    const auto through_manifest = local_inputs({manifest, "https://example.invalid/c.laz"});
    ASSERT_GE(through_manifest.size(), 2u);
    EXPECT_EQ(through_manifest[0], manifest);
    for (std::size_t i = 1; i < through_manifest.size(); ++i) {
        EXPECT_TRUE(fs::equivalent(through_manifest[i], tile)) << through_manifest[i];
    }
    fs::remove_all(dir);
}

}  // namespace
}  // namespace lidarscout::dataset
