// net/s3_request: s3 URLs as http(s) URLs (virtual-hosted and path-style, AWS and other
// endpoints, keys percent-encoded) and their signing; then against a real S3 server on loopback
// (tests/s3_server.hpp, which checks AWS Signature V4): a tile read through s3:// equals the
// local file, signed and anonymous; a wrong secret fails with SignatureDoesNotMatch and a
// missing key with NoSuchKey, naming the bucket and key and never the secret; a listing pages
// through continuation tokens. Against the fault server: the signing, session-token and
// requester-pays headers are sent (the secret never), SlowDown and 503 are retried, and a cut
// body resumes where it stopped.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <iterator>

#include "core/error.hpp"
#include "fault_server.hpp"
#include "io/file.hpp"
#include "net/remote_file.hpp"
#include "net/s3_request.hpp"
#include "s3_server.hpp"
#include "test_data.hpp"

namespace lidarscout::net {
namespace {

namespace fs = std::filesystem;
using test::Fault;

const char* const kTile = "surveys/ky-woodford-county/5205000_3900000.laz";

std::vector<std::uint8_t> whole_file(const fs::path& path) {
    std::ifstream in(path, std::ios::binary);
    return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

TEST(S3Request, UrlsOfEachAddressingStyle) {
    S3Config aws;
    aws.region = "eu-west-3";
    const S3Location tile{"lidar", "tiles/a b+c.laz"};
    EXPECT_EQ(s3_http_url(aws, tile), "https://lidar.s3.eu-west-3.amazonaws.com/tiles/a%20b%2Bc.laz");
    EXPECT_EQ(s3_http_url(aws, {"my.bucket", "k.laz"}), "https://s3.eu-west-3.amazonaws.com/my.bucket/k.laz");
    aws.addressing = "path";
    EXPECT_EQ(s3_http_url(aws, tile), "https://s3.eu-west-3.amazonaws.com/lidar/tiles/a%20b%2Bc.laz");
    S3Config minio;
    minio.endpoint = "http://127.0.0.1:9000";
    EXPECT_EQ(s3_http_url(minio, tile), "http://127.0.0.1:9000/lidar/tiles/a%20b%2Bc.laz");
    minio.addressing = "virtual";
    EXPECT_EQ(s3_http_url(minio, tile, "list-type=2"), "http://lidar.127.0.0.1:9000/tiles/a%20b%2Bc.laz?list-type=2");
}

TEST(S3Request, ParsedUrls) {
    const auto tile = parse_s3_url("S3://bucket/a/b.laz");
    ASSERT_TRUE(tile);
    EXPECT_EQ(tile->bucket, "bucket");
    EXPECT_EQ(tile->key, "a/b.laz");
    EXPECT_EQ(parse_s3_url("s3://bucket")->key, "");
    EXPECT_FALSE(parse_s3_url("s3:///key"));
    EXPECT_FALSE(parse_s3_url("https://bucket/key"));
    EXPECT_EQ(s3_error_context("s3://b/k.laz"), " (bucket \"b\", key \"k.laz\")");
    EXPECT_EQ(s3_error_context("https://b/k.laz"), "");
}

TEST(S3Request, SigningByLibcurlWithTheHeadersItNeeds) {
    S3Config c;
    c.requester_pays = true;
    RequestSigning s = s3_signing(c);  // anonymous: not signed, the requester still pays
    EXPECT_EQ(s.aws_sigv4, "");
    EXPECT_EQ(s.headers, std::vector<std::string>{"x-amz-request-payer: requester"});
    c.access_key = "AKIAX";
    c.secret_key = "secret";
    c.session_token = "token";
    c.region = "ca-central-1";
    s = s3_signing(c);
    EXPECT_EQ(s.aws_sigv4, "aws:amz:ca-central-1:s3");
    EXPECT_EQ(s.access_key, "AKIAX");
    EXPECT_EQ(s.secret, "secret");
    EXPECT_NE(std::find(s.headers.begin(), s.headers.end(), "x-amz-security-token: token"), s.headers.end());
}

// --- against the S3 server -------------------------------------------------------------

class S3ServerTest : public ::testing::Test {
protected:
    test::S3Server& server = test::S3Server::instance();

    void SetUp() override {
        static bool stored = false;
        if (!stored) {
            server.put_file("tiles", "woodford/5205000_3900000.laz", test::data_dir() / kTile);
            for (int i = 0; i < 7; ++i) server.put("tiles", "seven/k" + std::to_string(i) + ".txt", "x");
            stored = true;
        }
        set_s3_config(server.config());
        RemoteFile::forget_all();
    }
    void TearDown() override { set_s3_config(std::nullopt); }

    // The message of the error opening `url` ("" when it opens).
    static std::string open_error(const std::string& url) {
        try {
            io::File::open(url);
        } catch (const Error& e) {
            return e.what();
        }
        return {};
    }
};

TEST_F(S3ServerTest, ReadsEqualTheLocalFileSignedAndAnonymous) {
    const auto bytes = whole_file(test::data_dir() / kTile);
    for (const bool anonymous : {false, true}) {
        set_s3_config(server.config(anonymous ? "" : test::S3Server::kSecret));
        RemoteFile::forget_all();
        const auto f = io::File::open("s3://tiles/woodford/5205000_3900000.laz");
        EXPECT_EQ(f.path(), "s3://tiles/woodford/5205000_3900000.laz");
        ASSERT_EQ(f.size(), bytes.size());
        std::vector<std::uint8_t> got(bytes.size());
        for (std::uint64_t at = 0; at < bytes.size(); at += 1 << 20) {
            const std::size_t n = std::min<std::uint64_t>(1 << 20, bytes.size() - at);
            ASSERT_EQ(f.read_at(at, std::span(got).subspan(at, n)), n);
        }
        EXPECT_TRUE(got == bytes) << (anonymous ? "anonymous" : "signed");
    }
}

TEST_F(S3ServerTest, AWrongSecretFailsWithSignatureDoesNotMatchAndIsNeverShown) {
    set_s3_config(server.config("wrong-secret-8d1f"));
    const std::string error = open_error("s3://tiles/woodford/5205000_3900000.laz");
    EXPECT_NE(error.find("SignatureDoesNotMatch"), std::string::npos) << error;
    EXPECT_NE(error.find("403"), std::string::npos) << error;
    EXPECT_NE(error.find("bucket \"tiles\", key \"woodford/5205000_3900000.laz\""), std::string::npos) << error;
    EXPECT_EQ(error.find("wrong-secret-8d1f"), std::string::npos) << error;
}

TEST_F(S3ServerTest, AMissingKeyIsNoSuchKey) {
    const std::string error = open_error("s3://tiles/woodford/missing.laz");
    EXPECT_NE(error.find("404, error NoSuchKey"), std::string::npos) << error;
    EXPECT_NE(error.find("key \"woodford/missing.laz\""), std::string::npos) << error;
    EXPECT_NE(open_error("s3://tiles").find("needs a bucket and a key"), std::string::npos);
}

TEST_F(S3ServerTest, ListingPagesThroughContinuationTokens) {
    const auto before = HttpClient::shared().stats().requests;
    const auto objects = list_s3_objects("s3://tiles/seven/", 3);
    EXPECT_EQ(HttpClient::shared().stats().requests - before, 3u);  // 3 + 3 + 1 keys
    ASSERT_EQ(objects.size(), 7u);
    for (int i = 0; i < 7; ++i) {
        EXPECT_EQ(objects[i].key, "seven/k" + std::to_string(i) + ".txt");
        EXPECT_EQ(objects[i].size, 1u);
    }
    set_s3_config(server.config("wrong"));
    try {
        list_s3_objects("s3://tiles/seven/");
        FAIL() << "listed with a wrong secret";
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find("SignatureDoesNotMatch"), std::string::npos) << e.what();
        EXPECT_NE(std::string(e.what()).find("bucket \"tiles\", prefix \"seven/\""), std::string::npos) << e.what();
    }
}

// --- against the fault server ------------------------------------------------------------

std::vector<std::uint8_t> pattern(std::size_t n) {
    std::vector<std::uint8_t> v(n);
    for (std::size_t i = 0; i < n; ++i) v[i] = static_cast<std::uint8_t>((i * 131) ^ (i >> 8));
    return v;
}

class S3Faults : public ::testing::Test {
protected:
    S3Faults() : data(pattern(200000)), server(data), client(settings()) {}

    static HttpSettings settings() {
        HttpSettings s;
        s.retries = 3;
        s.backoff = std::chrono::milliseconds(5);
        return s;
    }
    void SetUp() override {
        S3Config c;
        c.endpoint = "http://127.0.0.1:" + server.url().substr(17, server.url().find('/', 17) - 17);
        c.access_key = "AKIATEST";
        c.secret_key = "never-shown-5e2a";
        c.session_token = "session-token-1";
        c.region = "eu-north-1";
        c.requester_pays = true;
        set_s3_config(c);
    }
    void TearDown() override { set_s3_config(std::nullopt); }
    RangeReply fetch(ByteRange r) { return client.fetch(remote_request("s3://bucket/file.bin", {r}, {})); }
    bool bytes_equal(const RangeReply& reply, ByteRange r) {
        return reply.error.empty() && reply.parts.at(0).size() == r.length &&
               std::equal(reply.parts[0].begin(), reply.parts[0].end(), data.begin() + r.offset);
    }

    std::vector<std::uint8_t> data;
    test::FaultServer server;
    HttpClient client;
};

TEST_F(S3Faults, SignatureTokenAndRequesterPaysHeadersAreSentNeverTheSecret) {
    ASSERT_TRUE(bytes_equal(fetch({10, 100}), {10, 100}));
    const auto heads = server.requests_seen();
    ASSERT_EQ(heads.size(), 1u);
    const std::string& head = heads[0];
    EXPECT_EQ(head.rfind("GET /bucket/file.bin HTTP/1.1", 0), 0u) << head;
    EXPECT_NE(head.find("x-amz-request-payer: requester"), std::string::npos) << head;
    EXPECT_NE(head.find("x-amz-security-token: session-token-1"), std::string::npos) << head;
    EXPECT_NE(head.find("Authorization: AWS4-HMAC-SHA256 Credential=AKIATEST/"), std::string::npos) << head;
    EXPECT_NE(head.find("/eu-north-1/s3/aws4_request"), std::string::npos) << head;
    EXPECT_EQ(head.find("never-shown-5e2a"), std::string::npos) << head;
}

TEST_F(S3Faults, SlowDownAnd503AreRetried) {
    server.inject(Fault::SlowDown, 2);
    EXPECT_TRUE(bytes_equal(fetch({0, 50}), {0, 50}));
    server.inject(Fault::ServiceUnavailable, 1);
    EXPECT_TRUE(bytes_equal(fetch({50, 50}), {50, 50}));
    EXPECT_GE(client.stats().retries, 3u);
    server.inject(Fault::SlowDown, 100);
    const RangeReply failed = fetch({0, 50});
    EXPECT_NE(failed.error.find("HTTP status 503, error SlowDown (Please reduce your request rate.)"),
              std::string::npos) << failed.error;
    EXPECT_NE(failed.error.find("after 4 attempts"), std::string::npos) << failed.error;
}

TEST_F(S3Faults, ACutBodyResumesWhereItStopped) {
    server.inject(Fault::DropMidBody);
    EXPECT_TRUE(bytes_equal(fetch({1000, 100000}), {1000, 100000}));
    const auto ranges = server.ranges_seen();
    ASSERT_EQ(ranges.size(), 2u);
    EXPECT_EQ(ranges[0], "bytes=1000-100999");
    EXPECT_EQ(ranges[1], "bytes=51000-100999");  // the second half only
}

}  // namespace
}  // namespace lidarscout::net
