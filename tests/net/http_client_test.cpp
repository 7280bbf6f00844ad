// net/http_client against the fault-injecting server: transient faults are retried (a cut
// body resumes where it stopped), definite ones are clear errors, and no response ever
// yields wrong bytes: a dropped connection, 503 then success, Range ignored, a wrong
// Content-Range, a truncated body, a slow response, a longer body, a changed ETag, a
// redirect to another scheme, and multi-range requests to a server without them. Hostile
// answers end bounded: a trickled body at its deadline, a lying Content-Length without
// retries, stray bytes with their own message, a redirect to another origin not followed.
// Over TLS (nginx with a test CA), requests in flight together share one HTTP/2 connection.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <future>
#include <iterator>

#include "fault_server.hpp"
#include "net/http_client.hpp"
#include "net/origin_policy.hpp"
#include "nginx_server.hpp"

namespace lidarscout::net {
namespace {

using test::Fault;
using test::FaultServer;

std::vector<std::uint8_t> pattern(std::size_t n) {
    std::vector<std::uint8_t> v(n);
    for (std::size_t i = 0; i < n; ++i) v[i] = static_cast<std::uint8_t>((i * 131) ^ (i >> 8));
    return v;
}

HttpSettings quick() {
    HttpSettings s;
    s.retries = 3;
    s.backoff = std::chrono::milliseconds(5);
    s.stall_timeout_s = 1;
    s.connect_timeout_s = 2;
    return s;
}

class HttpFaults : public ::testing::Test {
protected:
    HttpFaults() : data(pattern(300000)), server(data), client(quick()) {}

    RangeReply fetch(std::vector<ByteRange> ranges, std::string validator = {}) {
        return client.fetch({server.url(), std::move(ranges), std::move(validator)});
    }
    void expect_bytes(const RangeReply& r, const std::vector<ByteRange>& ranges) {
        ASSERT_EQ(r.error, "");
        ASSERT_EQ(r.parts.size(), ranges.size());
        for (std::size_t i = 0; i < ranges.size(); ++i) {
            ASSERT_EQ(r.parts[i].size(), ranges[i].length) << i;
            EXPECT_TRUE(std::equal(r.parts[i].begin(), r.parts[i].end(), data.begin() + ranges[i].offset)) << i;
        }
    }
    void expect_error(const RangeReply& r, const std::string& words) {
        EXPECT_TRUE(r.parts.empty());
        EXPECT_NE(r.error.find(words), std::string::npos) << r.error;
    }

    std::vector<std::uint8_t> data;
    FaultServer server;
    HttpClient client;
};

TEST_F(HttpFaults, CorrectAnswersPass) {
    const std::vector<ByteRange> r = {{1000, 5000}};
    const auto reply = fetch(r);
    expect_bytes(reply, r);
    EXPECT_EQ(reply.total, data.size());
    EXPECT_EQ(reply.validator, "\"v1\"");
    EXPECT_EQ(client.stats().requests, 1u);
}

// Thousands of requests to one origin at once: libcurl holds at most connections_per_host of them (the
// rest wait in the client, in order), since it walks its own queue of waiting handles on every removal.
TEST(HttpClient, ManyRequestsToOneOriginWaitInTheClient) {
    const auto data = pattern(4096);
    FaultServer server(data);
    HttpSettings s = quick();
    s.connections_per_host = 3;
    HttpClient client(s);
    std::vector<std::future<RangeReply>> replies;
    for (std::uint64_t i = 0; i < 2000; ++i) {
        auto promise = std::make_shared<std::promise<RangeReply>>();
        replies.push_back(promise->get_future());
        client.submit({server.url(), {{i % 4000, 17}}, {}}, [promise](RangeReply&& r) { promise->set_value(r); });
    }
    for (std::uint64_t i = 0; i < replies.size(); ++i) {
        const RangeReply r = replies[i].get();
        ASSERT_EQ(r.error, "") << i;
        ASSERT_EQ(r.parts.size(), 1u);
        EXPECT_TRUE(std::equal(r.parts[0].begin(), r.parts[0].end(), data.begin() + i % 4000)) << i;
    }
    EXPECT_EQ(client.stats().requests, 2000u);
    EXPECT_LE(client.stats().peak_transfers, 3u);
    EXPECT_GE(client.stats().peak_transfers, 1u);
}

TEST_F(HttpFaults, DroppedConnectionResumesWhereTheBodyStopped) {
    server.inject(Fault::DropMidBody);
    const std::vector<ByteRange> r = {{10000, 200000}};
    expect_bytes(fetch(r), r);
    const auto seen = server.ranges_seen();
    ASSERT_EQ(seen.size(), 2u);
    EXPECT_EQ(seen[0], "bytes=10000-209999");
    EXPECT_EQ(seen[1], "bytes=110000-209999");  // only the part that did not arrive
}

TEST_F(HttpFaults, ServiceUnavailableIsRetriedWithBackoff) {
    server.inject(Fault::ServiceUnavailable, 2);
    const std::vector<ByteRange> r = {{0, 100}};
    expect_bytes(fetch(r), r);
    EXPECT_EQ(server.requests(), 3);
    EXPECT_EQ(client.stats().retries, 2u);
}

TEST_F(HttpFaults, PersistentServiceUnavailableIsAnErrorAfterTheRetries) {
    server.inject(Fault::ServiceUnavailable, 100);
    expect_error(fetch({{0, 100}}), "HTTP status 503 (after 4 attempts)");
}

TEST_F(HttpFaults, IgnoredRangeIsAnErrorWithoutDownloadingTheFile) {
    server.inject(Fault::IgnoreRange);
    expect_error(fetch({{0, 100}}), "ignores Range");
    EXPECT_EQ(client.stats().body_bytes, 0u);
}

TEST_F(HttpFaults, WrongContentRangeIsAnError) {
    server.inject(Fault::WrongContentRange);
    expect_error(fetch({{500, 100}}), "answered bytes \"bytes 501-600/300000\" to a request for 500-599");
}

TEST_F(HttpFaults, TruncatedBodyIsCompletedOrAnError) {
    server.inject(Fault::TruncatedBody);
    const std::vector<ByteRange> r = {{20000, 30000}};
    expect_bytes(fetch(r), r);
    server.inject(Fault::TruncatedBody, 100);
    expect_error(fetch({{20000, 30000}}), "attempts)");
}

TEST_F(HttpFaults, SlowResponseTimesOutAndIsRetried) {
    server.inject(Fault::Slow);
    const std::vector<ByteRange> r = {{7, 70}};
    expect_bytes(fetch(r), r);
    EXPECT_EQ(server.requests(), 2);  // the slow answer was not waited out (it would have been the only request)
}

TEST_F(HttpFaults, LongerBodyIsRefused) {
    server.inject(Fault::LongerBody);
    expect_error(fetch({{0, 1000}}), "more bytes than were asked for");
}

TEST_F(HttpFaults, ChangedEtagIsAnError) {
    const auto first = fetch({{0, 10}});
    ASSERT_EQ(first.error, "");
    server.inject(Fault::NewEtag);
    expect_error(fetch({{10, 10}}, first.validator), "changed on the server during this session");
}

TEST_F(HttpFaults, RedirectToAnotherSchemeIsRefused) {
    server.inject(Fault::RedirectToHttps);
    expect_error(fetch({{0, 10}}), "redirect to another scheme is refused");
}

TEST_F(HttpFaults, MultiRangeFallsBackToSingleRangesWithoutAFullDownload) {
    const std::vector<ByteRange> r = {{0, 10}, {5000, 20}, {299990, 10}};
    expect_bytes(fetch(r), r);
    EXPECT_EQ(server.requests(), 4);  // the multi-range request (answered 200, not read), then one per range
    EXPECT_LT(client.stats().body_bytes, 1000u);
    expect_bytes(fetch(r), r);        // the server is now known: single ranges straight away
    EXPECT_EQ(server.requests(), 7);
}

// A server answering a multi-range request with one 206 range (the whole file) is asked range by
// range too, that body not downloaded.
TEST_F(HttpFaults, MultiRangeAnsweredByOneRangeFallsBackToSingleRanges) {
    server.multi_range_206 = true;
    const std::vector<ByteRange> r = {{0, 10}, {5000, 20}, {299990, 10}};
    expect_bytes(fetch(r), r);
    EXPECT_EQ(server.requests(), 4);
    EXPECT_LT(client.stats().body_bytes, 1000u);
}

// A request with a suffix (a remote file's head and tail in one, net/remote_file.hpp) to a server that
// answers several ranges with the whole file fails without downloading it, and the server is then known
// as one that does not answer them; one answered by one 206 range fails too, but tells nothing.
TEST_F(HttpFaults, ASuffixRequestIsNeverSplitNorAnsweredByAWholeLargeFile) {
    RangeRequest request{server.url(), {{0, 8192}}, {}};
    request.suffix = 2048;
    expect_error(client.fetch(request), "with the whole file");
    EXPECT_EQ(server.requests(), 1);
    EXPECT_LT(client.stats().body_bytes, 1000u);
    EXPECT_EQ(client.multi_range(server.url()), HttpClient::MultiRange::no);

    FaultServer joining(data);
    joining.multi_range_206 = true;
    RangeRequest joined{joining.url(), {{0, 8192}}, {}};
    joined.suffix = 2048;
    expect_error(client.fetch(joined), "with one range");
    EXPECT_EQ(joining.requests(), 1);
    EXPECT_EQ(client.multi_range(joining.url()), HttpClient::MultiRange::unknown);
}

TEST_F(HttpFaults, RangeAtTheEndOfTheFileMayBeShortened) {
    const auto reply = fetch({{data.size() - 10, 4096}});
    ASSERT_EQ(reply.error, "");
    ASSERT_EQ(reply.parts[0].size(), 10u);
    EXPECT_TRUE(std::equal(reply.parts[0].begin(), reply.parts[0].end(), data.end() - 10));
}

}  // namespace
}  // namespace lidarscout::net

namespace lidarscout::net {
namespace {

std::vector<std::uint8_t> file_bytes(const std::filesystem::path& path) {
    std::ifstream in(path, std::ios::binary);
    return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

TEST(HttpClient, Http2OverTlsMultiplexesRequestsOnOneConnection) {
    const auto& server = test::NginxServer::instance();
    const std::string rel = "surveys/ky-woodford-county/5205000_3900000.laz";
    const auto local = file_bytes(test::data_dir() / rel);
    HttpSettings settings;
    settings.ca_file = server.ca_file().string();
    HttpClient client(settings);
    constexpr std::size_t kRequests = 24;
    std::vector<std::promise<RangeReply>> replies(kRequests);
    std::vector<ByteRange> asked;
    for (std::size_t i = 0; i < kRequests; ++i) {  // all in flight at once, two ranges each
        asked.push_back({i * 40'000, 1'000 + i});
        const std::vector<ByteRange> ranges = {asked.back(), {local.size() - 2'000 - i, 500}};
        client.submit({server.https_url(rel), ranges, {}}, [&replies, i](RangeReply&& r) {
            replies[i].set_value(std::move(r));
        });
    }
    for (std::size_t i = 0; i < kRequests; ++i) {
        const RangeReply r = replies[i].get_future().get();
        ASSERT_EQ(r.error, "") << i;
        ASSERT_EQ(r.parts.size(), 2u);
        EXPECT_TRUE(std::equal(r.parts[0].begin(), r.parts[0].end(), local.begin() + asked[i].offset)) << i;
        EXPECT_EQ(r.parts[0].size(), asked[i].length);
        EXPECT_TRUE(std::equal(r.parts[1].begin(), r.parts[1].end(), local.end() - 2'000 - i)) << i;
    }
    const HttpStats stats = client.stats();
    EXPECT_EQ(stats.requests, kRequests);
    EXPECT_EQ(stats.http2_responses, kRequests);
    EXPECT_EQ(stats.connections, 1u);
}

// nginx's redirects: one within the scheme is followed for a ranged request, where it led
// given to the caller (who keeps it for the file); one from https to http is refused.
TEST(HttpClient, RedirectsWithinTheSchemeAreFollowedDowngradesRefused) {
    const auto& server = test::NginxServer::instance();
    const auto local = file_bytes(test::data_dir() / test::NginxServer::kRedirected);
    HttpSettings settings;
    settings.ca_file = server.ca_file().string();
    HttpClient client(settings);
    const RangeReply moved = client.fetch({server.url("moved.laz"), {{100, 50}}, {}});
    ASSERT_EQ(moved.error, "");
    EXPECT_TRUE(std::equal(moved.parts[0].begin(), moved.parts[0].end(), local.begin() + 100));
    EXPECT_EQ(moved.final_url, server.url(test::NginxServer::kRedirected));
    const RangeReply downgraded = client.fetch({server.https_url("downgrade.laz"), {{100, 50}}, {}});
    EXPECT_NE(downgraded.error.find("a redirect to another scheme is refused"), std::string::npos)
        << downgraded.error;
    EXPECT_TRUE(downgraded.parts.empty());
}

// nginx answers a head and a suffix in one multipart response (the server then known to answer several
// ranges), and a file smaller than both together with all of it (200), taken whole: one request each.
TEST(HttpClient, AHeadAndASuffixComeInOneRequestAndASmallFileWhole) {
    const auto& server = test::NginxServer::instance();
    HttpClient client;
    const std::string large = "surveys/ky-woodford-county/5205000_3900000.laz";
    const auto bytes = file_bytes(test::data_dir() / large);
    RangeRequest request{server.url(large), {{0, 8192}}, {}};
    request.suffix = 2048;
    EXPECT_EQ(client.multi_range(request.url), HttpClient::MultiRange::unknown);
    const RangeReply r = client.fetch(request);
    ASSERT_EQ(r.error, "");
    ASSERT_EQ(r.parts.size(), 2u);
    EXPECT_FALSE(r.whole_file);
    EXPECT_EQ(r.total, bytes.size());
    EXPECT_TRUE(std::vector<std::uint8_t>(bytes.begin(), bytes.begin() + 8192) == r.parts[0]);
    EXPECT_TRUE(std::vector<std::uint8_t>(bytes.end() - 2048, bytes.end()) == r.parts[1]);
    EXPECT_EQ(client.multi_range(request.url), HttpClient::MultiRange::yes);

    const std::string small = "surveys/nc-raleigh-ept/ept/3-3-5-4.laz";
    const auto small_bytes = file_bytes(test::data_dir() / small);
    ASSERT_LT(small_bytes.size(), 8192u + 2048u);
    request.url = server.url(small);
    const RangeReply whole = client.fetch(request);
    ASSERT_EQ(whole.error, "");
    EXPECT_TRUE(whole.whole_file);
    ASSERT_EQ(whole.parts.size(), 1u);
    EXPECT_TRUE(whole.parts[0] == small_bytes);
    EXPECT_EQ(whole.total, small_bytes.size());
    EXPECT_EQ(client.stats().requests, 2u);
}

TEST(HttpClient, PlainHttpIsHttp1) {
    const auto& server = test::NginxServer::instance();
    HttpClient client;
    const RangeReply r = client.fetch({server.url("surveys/ky-woodford-county/5205000_3900000.laz"), {{0, 100}}, {}});
    ASSERT_EQ(r.error, "");
    EXPECT_EQ(client.stats().http2_responses, 0u);
    EXPECT_EQ(client.stats().connections, 1u);
}

}  // namespace
}  // namespace lidarscout::net

// Hostile servers: each case ends bounded, with its own message.
namespace lidarscout::net {
namespace {

using test::Fault;
using test::FaultServer;

// A body trickled at ~100 bytes/s cannot hold a request past its deadline (here 0.5 s plus
// 4 KiB at 4 KiB/s), though it never stalls long enough for the stall time-out.
TEST_F(HttpFaults, TricklingBodyFailsAtItsDeadlineNamingTimeAndBytes) {
    HttpSettings s = quick();
    s.min_rate = 4096;
    s.deadline_grace = std::chrono::milliseconds(500);
    client.set_settings(s);
    server.inject(Fault::Trickle, 100);
    const auto reply = fetch({{0, 4096}});
    expect_error(reply, "then 4096 bytes/s; --min-rate)");
    EXPECT_NE(reply.error.find(" of 4096 bytes in "), std::string::npos) << reply.error;
    EXPECT_NE(reply.error.find("past its deadline of 1.5 s"), std::string::npos) << reply.error;
    EXPECT_LT(server.trickled_sends(), 2048);  // the body was not waited out
}

// A Content-Length larger than the Content-Range: the bytes arrive, the transfer ends badly,
// and the client neither retries nor asks for an empty range.
TEST_F(HttpFaults, LyingContentLengthIsAnErrorWithoutRetries) {
    server.inject(Fault::LyingLength, 100);
    expect_error(fetch({{0, 2048}}), "Content-Length does not match its Content-Range");
    EXPECT_EQ(server.ranges_seen(), std::vector<std::string>{"bytes=0-2047"});
}

// Bytes after a body on a kept-alive connection spoil the next response on it: its own
// message (no retries), or a retry on a fresh connection that succeeds.
TEST_F(HttpFaults, StrayBytesAfterABodyGetTheirOwnMessageAndARetry) {
    HttpSettings s = quick();
    s.retries = 0;
    client.set_settings(s);
    server.inject(Fault::StrayBytes);
    ASSERT_EQ(fetch({{0, 100}}).error, "");
    expect_error(fetch({{100, 100}}), "stray bytes after an earlier response on the same connection");
    client.set_settings(quick());
    server.inject(Fault::StrayBytes);
    ASSERT_EQ(fetch({{0, 100}}).error, "");
    const std::vector<ByteRange> r = {{100, 100}};
    expect_bytes(fetch(r), r);
}

// A redirect to another origin is not followed (no request reaches it) unless allowed.
TEST_F(HttpFaults, RedirectToAnotherOriginIsRefusedUnlessAllowed) {
    FaultServer other(data);
    server.redirect_to = other.url();
    server.inject(Fault::Redirect);
    const auto refused = fetch({{0, 10}});
    expect_error(refused, "another origin than the dataset's");
    EXPECT_NE(refused.error.find("--allow-origins"), std::string::npos) << refused.error;
    EXPECT_EQ(other.requests(), 0);
    set_allowed_origins(parse_allowed_origins(other.url()));
    server.inject(Fault::Redirect);
    const std::vector<ByteRange> r = {{0, 10}};
    expect_bytes(fetch(r), r);
    set_allowed_origins({});
    EXPECT_EQ(other.requests(), 1);
}

}  // namespace
}  // namespace lidarscout::net
