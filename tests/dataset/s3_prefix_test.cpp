// dataset/s3_prefix: an s3 prefix of 1,005 keys on the test S3 server (tests/s3_server.hpp)
// lists every point cloud in key order across two ListObjectsV2 pages, other objects left
// out; a prefix without tiles and a listing refused are errors naming the bucket and prefix;
// the file search expands a prefix like a folder.
#include <gtest/gtest.h>

#include <cstdio>

#include "core/error.hpp"
#include "dataset/file_search.hpp"
#include "dataset/s3_prefix.hpp"
#include "net/http_client.hpp"
#include "s3_server.hpp"

namespace lidarscout::dataset {
namespace {

constexpr int kKeys = 1005;

std::string key_name(int i) {
    char name[32];
    std::snprintf(name, sizeof name, "tiles/t%04d.laz", i);
    return name;
}

class S3Prefix : public ::testing::Test {
protected:
    test::S3Server& server = test::S3Server::instance();

    void SetUp() override {
        static bool stored = false;
        if (!stored) {
            for (int i = 0; i < kKeys; ++i) server.put("many", key_name(i), "not a real tile " + std::to_string(i));
            server.put("many", "tiles/README.txt", "not a tile");
            stored = true;
        }
        net::set_s3_config(server.config());
    }
    void TearDown() override { net::set_s3_config(std::nullopt); }
};

TEST_F(S3Prefix, ListsEveryTileAcrossPages) {
    EXPECT_TRUE(is_s3_prefix("s3://many/tiles/"));
    EXPECT_TRUE(is_s3_prefix("s3://many"));
    EXPECT_FALSE(is_s3_prefix("s3://many/tiles/t0001.laz"));
    EXPECT_FALSE(is_s3_prefix("/local/folder/"));
    const auto before = net::HttpClient::shared().stats().requests;
    const auto tiles = s3_prefix_tiles("s3://many/tiles/");
    EXPECT_EQ(net::HttpClient::shared().stats().requests - before, 2u);  // 1,000 keys, then 6
    ASSERT_EQ(tiles.size(), static_cast<std::size_t>(kKeys));
    for (int i = 0; i < kKeys; ++i) ASSERT_EQ(tiles[i], "s3://many/" + key_name(i));
}

TEST_F(S3Prefix, TheFileSearchExpandsAPrefixLikeAFolder) {
    const FoundFiles found = find_point_cloud_files({"s3://many/tiles/"});
    EXPECT_EQ(found.files.size(), static_cast<std::size_t>(kKeys));
    EXPECT_TRUE(found.errors.empty());
    const FoundFiles none = find_point_cloud_files({"s3://many/nothing-here/"});
    EXPECT_TRUE(none.files.empty());
    ASSERT_EQ(none.errors.size(), 1u);
    EXPECT_NE(none.errors[0].error.find("no .las/.laz object under this prefix (0 objects listed in bucket \"many\", "
                                        "prefix \"nothing-here/\")"),
              std::string::npos)
        << none.errors[0].error;
}

TEST_F(S3Prefix, AListingRefusedNamesBucketPrefixAndCode) {
    net::set_s3_config(server.config("not-the-secret-77"));
    try {
        s3_prefix_tiles("s3://many/tiles/");
        FAIL() << "listed with a wrong secret";
    } catch (const Error& e) {
        const std::string m = e.what();
        EXPECT_NE(m.find("SignatureDoesNotMatch"), std::string::npos) << m;
        EXPECT_NE(m.find("bucket \"many\", prefix \"tiles/\""), std::string::npos) << m;
        EXPECT_EQ(m.find("not-the-secret-77"), std::string::npos) << m;
    }
}

}  // namespace
}  // namespace lidarscout::dataset
