// dataset/s3_prefix: an s3 prefix of 1,005 keys on the test S3 server (tests/s3_server.hpp)
// lists every point cloud in key order across two ListObjectsV2 pages, other objects left
// out; a prefix without tiles and a listing refused are errors naming the bucket and prefix;
// the file search expands a prefix like a folder. Through the command line, against a hostile
// S3 server (tests/net/fault_server.hpp answering every request itself): a listing that would
// never end (the same token every page) stops after its second page with one line, on stderr and
// in --json, and `view` quits; an error body echoing the credentials shows none of them.
#include <gtest/gtest.h>

#include <atomic>
#include <cstdio>
#include <memory>

#include "core/error.hpp"
#include "dataset/file_search.hpp"
#include "dataset/s3_prefix.hpp"
#include "net/http_client.hpp"
#include "net/fault_server.hpp"
#include "s3_server.hpp"
#include "test_data.hpp"

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

// `s3://bucket/folder` (no trailing slash) where no object has that key but keys lie under folder/:
// opened as that prefix, as a local folder opens without its slash, with one note saying so, for one
// listing request of one key more; a key with neither says the open's error (NoSuchKey) alone.
TEST_F(S3Prefix, AUrlNamingAPrefixWithoutItsSlashOpensAsThePrefixWithANote) {
    const auto before = net::HttpClient::shared().stats().requests;
    const FoundFiles found = find_point_cloud_files({"s3://many/tiles"});
    const auto requests = net::HttpClient::shared().stats().requests - before;
    EXPECT_EQ(found.files.size(), static_cast<std::size_t>(kKeys));
    EXPECT_TRUE(found.errors.empty());
    ASSERT_EQ(found.warnings.size(), 1u);
    EXPECT_EQ(found.warnings[0].level, DiagnosticLevel::note);
    EXPECT_EQ(found.warnings[0].message,
              "s3://many/tiles is not an object: opened as the prefix s3://many/tiles/ (the objects under it)");
    EXPECT_EQ(requests, 4u) << "the object asked for, one key listed, the prefix's two pages";
    // "tile" is the start of keys ("tiles/..."), but no key lies under "tile/": no prefix to open.
    const FoundFiles none = find_point_cloud_files({"s3://many/tile"});
    EXPECT_TRUE(none.files.empty());
    EXPECT_TRUE(none.warnings.empty());
    ASSERT_EQ(none.errors.size(), 1u);
    EXPECT_NE(none.errors[0].error.find("NoSuchKey"), std::string::npos) << none.errors[0].error;
    EXPECT_NE(none.errors[0].error.find("bucket \"many\", key \"tile\""), std::string::npos) << none.errors[0].error;
    EXPECT_TRUE(s3_prefix_has_objects("s3://many/tiles/"));
    EXPECT_FALSE(s3_prefix_has_objects("s3://many/tile/"));
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

const std::string kSessionToken = "IQoJb3JpZ2luX2VjEPrefixTestSessionToken/9a8b+7c6==";
const std::string kSecretKey = "prefix-test-secret-6e5d4c";

std::shared_ptr<const std::string> xml_answer(const std::string& status, const std::string& xml) {
    return std::make_shared<const std::string>("HTTP/1.1 " + status + "\r\nContent-Type: application/xml\r\n"
                                               "Content-Length: " + std::to_string(xml.size()) + "\r\n\r\n" + xml);
}

class HostilePrefixCommand : public ::testing::Test {
protected:
    HostilePrefixCommand() : server(std::vector<std::uint8_t>{}) {
        server.respond = [this](const std::string&) {
            if (echo) {
                return xml_answer("403 Forbidden", "<Error><Code>" + kSessionToken + "</Code><Message>" + kSecretKey +
                                                       " " + kSessionToken + "</Message><Region>" + kSessionToken +
                                                       "</Region></Error>");
            }
            const std::string key = "k" + std::to_string(100000 + ++page) + ".laz";
            return xml_answer("200 OK", "<ListBucketResult><Contents><Key>" + key + "</Key><Size>100</Size>"
                                        "</Contents><IsTruncated>true</IsTruncated><NextContinuationToken>same"
                                        "</NextContinuationToken></ListBucketResult>");
        };
    }

    // Runs the command line with credentials for the server; stdout (and stderr when `both`) in `out`.
    int run(const std::string& args, std::string& out, bool both = true) {
        const std::string endpoint = server.url().substr(0, server.url().rfind('/'));
        const std::string env = "AWS_SHARED_CREDENTIALS_FILE=/dev/null "
                                "AWS_CONFIG_FILE=/dev/null AWS_ENDPOINT_URL=" + endpoint +
                                " AWS_ACCESS_KEY_ID=AKIAPREFIXTEST1 AWS_SECRET_ACCESS_KEY=" + kSecretKey +
                                " AWS_SESSION_TOKEN=" + kSessionToken + " ";
        return test::run_command(env + args + (both ? " 2>&1" : " 2>/dev/null"), out);
    }

    static void expect_no_credential(const std::string& out) {
        for (const std::string& secret : {kSessionToken, kSecretKey, std::string("AKIAPREFIXTEST1")}) {
            EXPECT_EQ(out.find(secret), std::string::npos) << out;
            EXPECT_EQ(out.find(secret.substr(0, 12)), std::string::npos) << out;
        }
    }

    test::FaultServer server;
    std::atomic<int> page{0};
    std::atomic<bool> echo{false};
};

std::size_t count_of(const std::string& text, const std::string& what) {
    std::size_t n = 0;
    for (auto at = text.find(what); at != std::string::npos; at = text.find(what, at + 1)) ++n;
    return n;
}

TEST_F(HostilePrefixCommand, AListingThatWouldNeverEndStopsWithOneLine) {
    std::string out;
    EXPECT_NE(run(std::string(LIDARSCOUT_CLI) + " scan s3://loop/", out), 0);
    EXPECT_EQ(count_of(out, "continuation token it gave before (page 2)"), 1u) << out;
    EXPECT_EQ(server.requests(), 2);
    expect_no_credential(out);
    EXPECT_NE(run(std::string(LIDARSCOUT_CLI) + " scan --json s3://loop/", out, false), 0);
    EXPECT_EQ(count_of(out, "continuation token it gave before (page 2)"), 1u) << out;  // (stdout: the JSON)
    EXPECT_EQ(server.requests(), 4);
    expect_no_credential(out);
    if (std::system("command -v xvfb-run >/dev/null 2>&1") != 0) GTEST_SKIP() << "xvfb-run not found";
    run("timeout 120 xvfb-run -a -s '-screen 0 640x480x24' " + std::string(LIDARSCOUT_CLI) +
        " view s3://loop/ --no-cnn --size 320x240 --quit-after 5",
        out);
    EXPECT_NE(out.find("continuation token it gave before (page 2)"), std::string::npos) << out;
    EXPECT_EQ(server.requests(), 6);
}

TEST_F(HostilePrefixCommand, CredentialsEchoedInAnErrorAreNeverShown) {
    echo = true;
    std::string out;
    EXPECT_NE(run(std::string(LIDARSCOUT_CLI) + " scan s3://loop/", out), 0);
    EXPECT_NE(out.find("HTTP status 403, error [redacted] ([redacted] [redacted]), Region [redacted]"),
              std::string::npos)
        << out;
    expect_no_credential(out);
    EXPECT_NE(run(std::string(LIDARSCOUT_CLI) + " scan --json s3://loop/", out), 0);
    EXPECT_NE(out.find("\"error\""), std::string::npos) << out;
    expect_no_credential(out);
    EXPECT_NE(run(std::string(LIDARSCOUT_CLI) + " info --json s3://loop/t.laz", out), 0);
    EXPECT_NE(out.find("403, error [redacted]"), std::string::npos) << out;
    expect_no_credential(out);
    EXPECT_EQ(server.requests(), 3);
}

}  // namespace
}  // namespace lidarscout::dataset
