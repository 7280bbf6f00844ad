// net/s3_request: s3 URLs as http(s) URLs (virtual-hosted and path-style, AWS and other
// endpoints, keys percent-encoded) and their signing; then against a real S3 server on loopback
// (tests/s3_server.hpp, which checks AWS Signature V4): a tile read through s3:// equals the
// local file, signed and anonymous; a wrong secret fails with SignatureDoesNotMatch and a
// missing key with NoSuchKey, naming the bucket and key and never the secret; a listing pages
// through continuation tokens. Against the fault server: the signing, session-token and
// requester-pays headers are sent (the secret never), SlowDown and 503 are retried, a cut
// body resumes where it stopped, and requests are built from the normalised key. Against a
// hostile S3 server (the fault server answering every request itself): the same token every
// page, pages without keys, too many keys, a huge page, keys that leave their bucket or prefix
// (however they spell ".."), and credentials echoed in an error's Code, Message and Region or in
// a header: each one line, its requests counted, nothing holding a credential.
#include <gtest/gtest.h>

#include <algorithm>
#include <atomic>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iterator>

#include "allocation_counter.hpp"
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

// The message of the error `f` throws ("" when it throws none).
std::string error_of(const std::function<void()>& f) {
    try {
        f();
    } catch (const Error& e) {
        return e.what();
    }
    return {};
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
    static std::string open_error(const std::string& url) { return error_of([&] { io::File::open(url); }); }
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
    const auto objects = list_s3_objects("s3://tiles/seven/", {.page_size = 3});
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

TEST_F(S3Faults, RequestsAreBuiltFromTheNormalisedKey) {
    const ByteRange r{0, 10};
    for (const char* url : {"s3://bucket/a/./b/../x.bin", "s3://bucket/a/%2e%2e/x.bin", "s3://bucket/a/&#46;/x.bin"}) {
        const RangeRequest request = remote_request(url, {r}, {});
        EXPECT_TRUE(request.path_as_is);
        EXPECT_TRUE(bytes_equal(client.fetch(request), r)) << url;
    }
    const auto heads = server.requests_seen();
    ASSERT_EQ(heads.size(), 3u);
    EXPECT_EQ(heads[0].rfind("GET /bucket/a/x.bin HTTP/1.1", 0), 0u) << heads[0];
    EXPECT_EQ(heads[1].rfind("GET /bucket/x.bin HTTP/1.1", 0), 0u) << heads[1];
    EXPECT_EQ(heads[2].rfind("GET /bucket/a/x.bin HTTP/1.1", 0), 0u) << heads[2];
    for (const char* url : {"s3://bucket/../secret/x.bin", "s3://bucket/%2e%2e/secret/x.bin",
                            "s3://bucket/a/../../secret/x.bin", "s3://bucket/&#46;&#46;/secret/x.bin"}) {
        const std::string error = error_of([&] { remote_request(url, {r}, {}); });
        EXPECT_NE(error.find(" leaves its bucket (a \"..\" segment"), std::string::npos) << url << ": " << error;
    }
    EXPECT_THROW(remote_request("s3://evil.example?/x.bin", {r}, {}), Error);  // (a bucket name S3 never has)
    EXPECT_THROW(remote_request("s3://bucket/a/..", {r}, {}), Error);         // (no key left)
    EXPECT_EQ(server.requests(), 3);
}

// --- against a hostile S3 server -----------------------------------------------------------

const std::string kAccessKey = "AKIAHOSTILE0TEST";
const std::string kSecretKey = "hostile-secret-never-shown-1f2e3d";
const std::string kSessionToken = "FwoGZXIvYXdzEBYaDHostileSessionToken/4b3a+2c1d0e9f8==";

std::shared_ptr<const std::string> http_answer(const std::string& status, const std::string& body,
                                               const std::string& headers = "Content-Type: application/xml\r\n") {
    return std::make_shared<const std::string>("HTTP/1.1 " + status + "\r\n" + headers + "Content-Length: " +
                                               std::to_string(body.size()) + "\r\n\r\n" + body);
}

// A ListObjectsV2 page of `keys` (written into the XML as they are), truncated when `token` is given.
std::shared_ptr<const std::string> list_page(const std::vector<std::string>& keys, const std::string& token) {
    std::string xml = "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n<ListBucketResult><Name>loop</Name>";
    for (const auto& k : keys) xml += "<Contents><Key>" + k + "</Key><Size>1000</Size></Contents>";
    xml += "<IsTruncated>" + std::string(token.empty() ? "false" : "true") + "</IsTruncated>";
    if (!token.empty()) xml += "<NextContinuationToken>" + token + "</NextContinuationToken>";
    return http_answer("200 OK", xml + "</ListBucketResult>");
}

std::string numbered(const char* format, int i) {
    char name[64];
    std::snprintf(name, sizeof name, format, i);
    return name;
}

class HostileS3 : public ::testing::Test {
protected:
    HostileS3() : server(pattern(1000)) {}
    void SetUp() override {
        S3Config c;
        c.endpoint = "http://127.0.0.1:" + server.url().substr(17, server.url().find('/', 17) - 17);
        c.access_key = kAccessKey;
        c.secret_key = kSecretKey;
        c.session_token = kSessionToken;
        set_s3_config(c);
    }
    void TearDown() override { set_s3_config(std::nullopt); }

    // The error listing `url` ends with (a failure when it lists), checked to be one line
    // without any credential.
    static std::string listing_error(const std::string& url, const S3ListLimits& limits = {}) {
        return checked(error_of([&] { list_s3_objects(url, limits); }));
    }
    // The same of opening `url` as a remote file.
    static std::string opening_error(const std::string& url) {
        RemoteFile::forget_all();
        return checked(error_of([&] { RemoteFile::open(url); }));
    }
    static std::string checked(const std::string& error) {
        EXPECT_NE(error, "") << "no error";
        expect_shown_safely(error);
        return error;
    }
    static void expect_shown_safely(const std::string& message) {
        EXPECT_EQ(message.find('\n'), std::string::npos) << message;
        EXPECT_LT(message.size(), 1200u) << message;
        for (const auto& secret : {kAccessKey, kSecretKey, kSessionToken}) {
            EXPECT_EQ(message.find(secret), std::string::npos) << message;
            EXPECT_EQ(message.find(secret.substr(0, 12)), std::string::npos) << message;
        }
    }

    test::FaultServer server;
    std::atomic<int> page{0};
};

TEST_F(HostileS3, TheSameTokenEveryPageStopsAtTheSecondPage) {
    server.respond = [&](const std::string&) { return list_page({numbered("k%06d.laz", ++page)}, "same-token"); };
    const std::string error = listing_error("s3://loop/");
    EXPECT_NE(error.find("s3://loop/: cannot be listed: the server gave a continuation token it gave before (page 2) "
                         "(bucket \"loop\", prefix \"\")"),
              std::string::npos)
        << error;
    EXPECT_EQ(server.requests(), 2);
}

TEST_F(HostileS3, TheSameKeysEveryPageStopAtTheSecondPage) {
    server.respond = [&](const std::string&) { return list_page({"a.laz", "b.laz"}, numbered("token-%d", ++page)); };
    const std::string error = listing_error("s3://loop/");
    EXPECT_NE(error.find("the key \"a.laz\" does not come after \"b.laz\""), std::string::npos) << error;
    EXPECT_EQ(server.requests(), 2);
}

TEST_F(HostileS3, PagesWithoutKeysCountTowardThePageCap) {
    server.respond = [&](const std::string&) { return list_page({}, numbered("token-%d", ++page)); };
    const std::string error = listing_error("s3://loop/");
    EXPECT_NE(error.find("cannot be listed: more than 5000 pages"), std::string::npos) << error;
    EXPECT_EQ(server.requests(), 5000);  // (the default limits)
    EXPECT_EQ(server.requests_seen().back().find(kSecretKey), std::string::npos);
}

TEST_F(HostileS3, KeysAndTheirBytesAreCapped) {
    server.respond = [&](const std::string&) {
        const int p = ++page;
        std::vector<std::string> keys;
        for (int i = 0; i < 10; ++i) keys.push_back(numbered("k%06d.laz", p * 10 + i));
        return list_page(keys, numbered("token-%d", p));
    };
    std::string error = listing_error("s3://loop/", {.page_size = 10, .max_keys = 25});
    EXPECT_NE(error.find("more than 25 keys"), std::string::npos) << error;
    EXPECT_EQ(server.requests(), 3);
    error = listing_error("s3://loop/", {.page_size = 10, .max_kept_bytes = 1u << 10});  // (11 bytes a key)
    EXPECT_NE(error.find("the keys listed take more than"), std::string::npos) << error;
    EXPECT_EQ(server.requests(), 3 + 10);  // 94 keys of 11 bytes fit, the 94th is on page 10
    std::uint64_t seen = 0;  // a visitor that keeps nothing holds nothing: only the key cap stops it
    page = 0;
    error = error_of([&] {
        for_each_s3_object("s3://loop/", [&](S3Object&&) { return ++seen, false; },
                           {.page_size = 10, .max_keys = 95, .max_kept_bytes = 0});
    });
    EXPECT_NE(error.find("more than 95 keys"), std::string::npos) << error;
    EXPECT_EQ(seen, 95u);
}

TEST_F(HostileS3, AHugePageOrOneWithMoreKeysThanAskedIsRefused) {
    std::string huge;  // 9 MiB of keys, one page
    for (int i = 0; huge.size() < (9u << 20); ++i) {
        huge += "<Contents><Key>" + numbered("k%08d.laz", i) + "</Key></Contents>";
    }
    const auto answer = http_answer("200 OK", "<ListBucketResult>" + huge + "<IsTruncated>false</IsTruncated>");
    huge.clear();
    huge.shrink_to_fit();
    server.respond = [&](const std::string&) { return answer; };
    std::size_t allocated = 0;
    std::string error;
    {
        test::AllocationCounter counter;
        error = listing_error("s3://loop/");
        allocated = counter.bytes();
    }
    EXPECT_NE(error.find("the response is larger than the 8388608 bytes accepted"), std::string::npos) << error;
    EXPECT_EQ(server.requests(), 1);
    EXPECT_LT(allocated, 24u << 20);  // (the 8 MiB kept, as its vector grew)

    std::vector<std::string> keys;
    for (int i = 0; i < 1001; ++i) keys.push_back(numbered("k%06d.laz", i));
    const auto page1001 = list_page(keys, "");
    server.respond = [&](const std::string&) { return page1001; };
    error = listing_error("s3://loop/");
    EXPECT_NE(error.find("page 1 holds more than the 1000 keys asked for"), std::string::npos) << error;
    EXPECT_EQ(server.requests(), 2);
}

TEST_F(HostileS3, KeysLeavingTheirBucketOrPrefixAreRefusedHoweverSpelled) {
    const std::vector<std::string> spellings = {"../secret/t.laz", "&#46;&#46;/secret/t.laz", "a/../../secret/t.laz",
                                                "%2e%2e/secret/t.laz", "&amp;#46;&amp;#46;/secret/t.laz"};
    std::string key;
    server.respond = [&](const std::string&) { return list_page({"a.laz", key}, ""); };
    int requests = 0;
    for (const auto& spelling : spellings) {
        key = spelling;
        const std::string error = listing_error("s3://dots/");
        EXPECT_NE(error.find("s3://dots/: cannot be listed: the key \""), std::string::npos) << error;
        EXPECT_NE(error.find("\" leaves its bucket"), std::string::npos) << error;
        EXPECT_EQ(server.requests(), ++requests);  // the listing's one: nothing read under that key
    }
    key = "tiles/../secret/t.laz";
    server.respond = [&](const std::string&) { return list_page({"tiles/a.laz", key}, ""); };
    std::string error = listing_error("s3://dots/tiles/");
    EXPECT_NE(error.find("the key \"tiles/../secret/t.laz\" leaves the prefix listed (\"tiles/\")"),
              std::string::npos)
        << error;
    key = "tiles/x/../b.laz";  // inside: listed by its normalised key
    const auto objects = list_s3_objects("s3://dots/tiles/");
    ASSERT_EQ(objects.size(), 2u);
    EXPECT_EQ(objects[1].key, "tiles/b.laz");
    key = "tiles/" + std::string(1100, 'k');
    error = listing_error("s3://dots/tiles/");
    EXPECT_NE(error.find("\" is longer than S3's 1024 bytes (1106)"), std::string::npos) << error;
    for (const auto& head : server.requests_seen()) EXPECT_EQ(head.find("secret/t.laz"), std::string::npos) << head;
}

// An S3 error body whose every element echoes the credentials, at length.
std::string echoing_error_body() {
    std::string echo;
    for (int i = 0; i < 50; ++i) echo += kSessionToken + " " + kSecretKey + " " + kAccessKey + " ";
    return "<?xml version=\"1.0\"?><Error><Code>" + kSessionToken + "</Code><Message>" + echo +
           "</Message><Region>" + kSessionToken + "</Region><Endpoint>" + kAccessKey + "</Endpoint></Error>";
}

TEST_F(HostileS3, CredentialsEchoedByTheServerAreNeverShown) {
    const auto forbidden = http_answer("403 Forbidden", echoing_error_body());
    server.respond = [&](const std::string&) { return forbidden; };
    const std::string listing = listing_error("s3://loop/");
    EXPECT_NE(listing.find("HTTP status 403, error [redacted] ([redacted]"), std::string::npos) << listing;
    EXPECT_NE(listing.find(", Region [redacted], Endpoint [redacted]"), std::string::npos) << listing;
    EXPECT_NE(listing.find("... ("), std::string::npos) << listing;  // the message cut, its length named
    std::string error = opening_error("s3://loop/t.laz");
    EXPECT_NE(error.find("403, error [redacted]"), std::string::npos) << error;
    // echoed in headers: Content-Range and ETag
    const auto echo_range = http_answer("206 Partial Content", std::string(10, 'x'), "ETag: \"" + kSessionToken +
                                        "\"\r\nContent-Range: bytes 0-9/" + kSecretKey + "\r\n");
    server.respond = [&](const std::string&) { return echo_range; };
    error = opening_error("s3://loop/t.laz");
    EXPECT_NE(error.find("the server answered bytes \"bytes 0-9/[redacted]\""), std::string::npos) << error;
    EXPECT_EQ(server.requests(), 3);
}

TEST_F(HostileS3, AFailingPageStopsTheListingWithOneLine) {
    server.respond = [&](const std::string&) {
        return ++page == 1 ? list_page({"a.laz"}, "next") : http_answer("404 Not Found", "<Error><Code>NoSuchBucket"
                                                                                      "</Code></Error>");
    };
    const std::string error = listing_error("s3://loop/");
    EXPECT_NE(error.find("s3://loop/: cannot be listed: HTTP status 404, error NoSuchBucket (page 2) (bucket \"loop\""),
              std::string::npos)
        << error;
    EXPECT_EQ(server.requests(), 2);
}

}  // namespace
}  // namespace lidarscout::net
