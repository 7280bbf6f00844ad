// dataset/file_search with URLs: a remote tile list's relative entries resolve against its
// URL and keep its origin (others only when allowed, never http after https), a local list
// may name URLs, a URL to a LAS/LAZ file is a tile, a list that cannot be fetched is
// reported, and a URL whose password holds an unencoded '#' is refused unread; the local
// inputs behind lists and manifests.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "dataset/file_search.hpp"
#include "net/fault_server.hpp"
#include "net/http_client.hpp"
#include "net/origin_policy.hpp"
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
    EXPECT_EQ(found.files, (std::vector<std::string>{server.url("surveys/ky-woodford-county/5205000_3900000.laz"),
                                                     server.url("lists/sub/a.laz")}));
    ASSERT_EQ(found.errors.size(), 1u);  // another origin, not allowed
    EXPECT_NE(found.errors[0].error.find("http://example.invalid/b.laz: refused"), std::string::npos)
        << found.errors[0].error;
    net::set_allowed_origins(net::parse_allowed_origins("http://example.invalid"));
    const auto allowed = find_point_cloud_files({server.url("lists/relative.txt")});
    net::set_allowed_origins({});
    EXPECT_TRUE(allowed.errors.empty());
    EXPECT_EQ(allowed.files.back(), "http://example.invalid/b.laz");
}

// Entries naming another origin (absolute, or "//host/..."), or http from an https list:
// refused with the reason, and nothing is fetched from them.
TEST(FileSearch, RemoteListEntriesKeepTheListsSchemeAndOrigin) {
    const auto& server = test::NginxServer::instance();
    test::FaultServer other({1, 2, 3});
    const std::string host = other.url().substr(7, other.url().find('/', 7) - 7);
    std::ofstream(server.lists_dir() / "hostile.txt") << "http://" << host << "/tiles.txt\n//" << host << "/x.laz\n";
    const auto found = find_point_cloud_files({server.url("lists/hostile.txt")});
    EXPECT_TRUE(found.files.empty());
    ASSERT_EQ(found.errors.size(), 2u);
    for (const auto& e : found.errors) {
        EXPECT_NE(e.error.find("another origin than the dataset's"), std::string::npos) << e.error;
    }
    EXPECT_EQ(other.requests(), 0);

    std::ofstream(server.lists_dir() / "downgrade.txt") << "http://127.0.0.1:" << server.port() << "/x.laz\n";
    const auto settings = net::HttpClient::shared().settings();
    auto with_ca = settings;
    with_ca.ca_file = server.ca_file().string();
    net::HttpClient::shared().set_settings(with_ca);
    net::set_allowed_origins(net::parse_allowed_origins("*"));
    const auto downgraded = find_point_cloud_files({server.https_url("lists/downgrade.txt")});
    net::set_allowed_origins({});
    net::HttpClient::shared().set_settings(settings);
    EXPECT_TRUE(downgraded.files.empty());
    ASSERT_EQ(downgraded.errors.size(), 1u);
    EXPECT_NE(downgraded.errors[0].error.find("downgrade from https to http is refused"), std::string::npos)
        << downgraded.errors[0].error;
}

// "http://u:pa#ss@host/..." would send "u:pa" to "host" (the rest a fragment) and was taken
// for a tile list: refused, unread, the password not shown.
TEST(FileSearch, PasswordWithAnUnencodedHashIsRefusedWithAHint) {
    test::FaultServer server({1, 2, 3});
    const std::string host = server.url().substr(7, server.url().find('/', 7) - 7);
    const auto found = find_point_cloud_files({"http://reader:pa#ss@" + host + "/tiles"});
    EXPECT_TRUE(found.files.empty());
    ASSERT_EQ(found.errors.size(), 1u);
    EXPECT_NE(found.errors[0].error.find("percent-encode them (%23, %3F, %2F)"), std::string::npos)
        << found.errors[0].error;
    EXPECT_EQ(found.errors[0].error.find("pa#ss"), std::string::npos) << found.errors[0].error;
    EXPECT_EQ(found.errors[0].error.find("reader"), std::string::npos) << found.errors[0].error;
    EXPECT_EQ(server.requests(), 0);
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
