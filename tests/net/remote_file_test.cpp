// net/remote_file through io::File against nginx on loopback: remote reads equal the local
// file's bytes everywhere, a tile's ranges go out as one multi-range request, URLs are shown
// without credentials, a file that changes on the server during a session is an error, and
// open() joins a prefetch in flight (threads opening one file at once share it); redirects are
// kept per file and resolved again when they expire; a server without validator that switches
// files is told by the file's size. Ranges read together are one request.
#include <gtest/gtest.h>

#include <atomic>
#include <filesystem>
#include <fstream>
#include <future>
#include <iterator>

#include "core/error.hpp"
#include "delay_proxy.hpp"
#include "fault_server.hpp"
#include "io/file.hpp"
#include "net/http_client.hpp"
#include "net/origin_policy.hpp"
#include "net/range_cache.hpp"
#include "net/remote_file.hpp"
#include "nginx_server.hpp"
#include "test_data.hpp"

namespace lidarscout::net {
namespace {

namespace fs = std::filesystem;

const char* const kTile = "surveys/ky-woodford-county/5205000_3900000.laz";

std::vector<std::uint8_t> whole_file(const fs::path& path) {
    std::ifstream in(path, std::ios::binary);
    return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

TEST(RemoteFile, ReadsEqualTheLocalFile) {
    const auto& server = test::NginxServer::instance();
    const auto bytes = whole_file(test::data_dir() / kTile);
    const auto f = io::File::open(server.url(kTile));
    EXPECT_EQ(f.path(), server.url(kTile));
    ASSERT_EQ(f.size(), bytes.size());
    const std::uint64_t n = bytes.size();
    for (const std::uint64_t at : {std::uint64_t{0}, std::uint64_t{4090}, n / 3, n - 5000, n - 4096, n - 3}) {
        for (const std::size_t len : {1u, 8u, 9000u}) {
            std::vector<std::uint8_t> got(len);
            const std::size_t read = f.read_at(at, got);
            ASSERT_EQ(read, std::min<std::uint64_t>(len, n - at)) << at;
            EXPECT_TRUE(std::equal(got.begin(), got.begin() + read, bytes.begin() + at)) << at << " " << len;
        }
    }
    EXPECT_THROW(f.read_vector(n - 10, 20), Error);
}

TEST(RemoteFile, ManyRangesAreOneMultiRangeRequest) {
    const auto& server = test::NginxServer::instance();
    const auto bytes = whole_file(test::data_dir() / kTile);
    const auto f = RemoteFile::open(server.url(kTile));
    std::vector<ByteRange> ranges;
    for (std::uint64_t i = 0; i < 200; ++i) ranges.push_back({i * 30011 + 17, 20 + i % 7});
    const auto before = HttpClient::shared().stats();
    std::promise<RangeReply> promise;
    f->fetch_async(ranges, [&](RangeReply&& r) { promise.set_value(std::move(r)); });
    const RangeReply reply = promise.get_future().get();
    const auto after = HttpClient::shared().stats();
    ASSERT_EQ(reply.error, "");
    EXPECT_EQ(after.requests - before.requests, 1u);
    ASSERT_EQ(reply.parts.size(), ranges.size());
    for (std::size_t i = 0; i < ranges.size(); ++i) {
        ASSERT_EQ(reply.parts[i].size(), ranges[i].length);
        EXPECT_TRUE(std::equal(reply.parts[i].begin(), reply.parts[i].end(), bytes.begin() + ranges[i].offset)) << i;
    }
}

// io::File::read_ranges: a remote file's ranges in one request (a LAZ tile's chunks, a tile's chunk points, read
// together), each equal to the local file's bytes, as a local file's are; a range past the end is an Error.
TEST(RemoteFile, ReadRangesIsOneRequestEqualToTheLocalBytes) {
    const auto& server = test::NginxServer::instance();
    net::RangeCache::configure({{}, 0});  // every range from the server
    const auto local = io::File::open((test::data_dir() / kTile).string());
    const auto remote = io::File::open(server.url(kTile) + "?read_ranges=1");
    std::vector<std::pair<std::uint64_t, std::uint64_t>> ranges;
    for (std::uint64_t i = 0; i < 40; ++i) ranges.emplace_back(10'000 + i * 50'021, 300 + i);
    ranges.emplace_back(20, 0);  // (an empty one: empty bytes, no range asked)
    const auto before = HttpClient::shared().stats().requests;
    const auto got = remote.read_ranges(ranges);
    EXPECT_EQ(HttpClient::shared().stats().requests - before, 1u);
    EXPECT_EQ(got, local.read_ranges(ranges));
    ASSERT_EQ(got.size(), ranges.size());
    EXPECT_EQ(got[3], local.read_vector(ranges[3].first, ranges[3].second));
    EXPECT_TRUE(got.back().empty());
    const std::vector<std::pair<std::uint64_t, std::uint64_t>> past{{10, 5}, {remote.size() - 4, 8}};
    EXPECT_THROW((void)remote.read_ranges(past), Error);
    EXPECT_THROW((void)local.read_ranges(past), Error);
}

TEST(RemoteFile, CredentialsAreNeverShown) {
    const auto& server = test::NginxServer::instance();
    const std::string with_secret = "http://someone:s3cr3t@127.0.0.1:" + std::to_string(server.port()) + "/";
    const auto f = io::File::open(with_secret + kTile);  // nginx asks for no credentials
    EXPECT_EQ(f.path(), server.url(kTile));
    try {
        io::File::open(with_secret + "surveys/missing.laz");
        FAIL() << "a missing file opened";
    } catch (const Error& e) {
        EXPECT_EQ(std::string(e.what()).find("s3cr3t"), std::string::npos) << e.what();
        EXPECT_NE(std::string(e.what()).find("404"), std::string::npos) << e.what();
    }
}

// prefetch returns before its requests end (behind a 400 ms round trip); the open() that
// follows waits for the file in flight instead of asking again, and a prefetch that failed is
// reported by open().
TEST(RemoteFile, OpenJoinsThePrefetchInFlight) {
    const auto& server = test::NginxServer::instance();
    const test::DelayProxy proxy(server.port(), std::chrono::milliseconds(200));
    const std::string base = "http://127.0.0.1:" + std::to_string(proxy.port()) + "/surveys/";
    net::RangeCache::configure({{}, 0});  // every range from the server
    const std::vector<std::string> urls = {base + "ky-jmo335-eastern-kentucky/N117E379.laz",
                                           base + "ky-woodford-county/missing.laz"};
    const auto before = net::HttpClient::shared().stats();
    io::File::prefetch(urls);
    // returned before any answer came back (each is 400 ms away): nothing received yet
    EXPECT_EQ(net::HttpClient::shared().stats().body_bytes - before.body_bytes, 0u);
    const auto f = net::RemoteFile::open(urls[0]);
    EXPECT_GT(net::HttpClient::shared().stats().body_bytes - before.body_bytes, 0u);  // open() waited for it
    // the head and tail in one request (nginx answers several ranges at once); the missing file's, sent
    // when that first answer of the origin came (or before, where the origin was known)
    EXPECT_LE(net::HttpClient::shared().stats().requests - before.requests, 2u);
    EXPECT_EQ(f->size(), fs::file_size(test::data_dir() / "surveys/ky-jmo335-eastern-kentucky/N117E379.laz"));
    EXPECT_THROW(net::RemoteFile::open(urls[1]), Error);
}

// Threads that open one file at once (behind a 200 ms round trip) share one opening: two requests
// (head, tail), not two per thread; a prefetch that ends between two looks of open() is not asked
// again either (the race that gave the replica server's scan a few requests more than 3 a tile).
TEST(RemoteFile, ThreadsOpeningOneFileShareItsOpening) {
    const auto& server = test::NginxServer::instance();
    const test::DelayProxy proxy(server.port(), std::chrono::milliseconds(100));
    const std::string url = "http://127.0.0.1:" + std::to_string(proxy.port()) +
                            "/surveys/ky-jmo335-eastern-kentucky/N117E380.laz";
    net::RangeCache::configure({{}, 0});
    const auto before = net::HttpClient::shared().stats();
    std::vector<std::future<std::shared_ptr<const RemoteFile>>> opened;
    for (int i = 0; i < 8; ++i) opened.push_back(std::async(std::launch::async, [&] { return RemoteFile::open(url); }));
    const auto first = opened.front().get();
    for (std::size_t i = 1; i < opened.size(); ++i) EXPECT_EQ(opened[i].get(), first);
    EXPECT_LE(net::HttpClient::shared().stats().requests - before.requests, 2u);  // (one where its host is known)
}

// A document opened to be read from its start costs one request, whose bytes come with the file (its head keeps
// the first 2 KiB, no tail asked); a small one comes whole; a file open already comes with nothing beside it, and
// no request; a missing one is an Error, and open() reports it again.
TEST(RemoteFile, OpenFromStartIsOneRequestForTheFirstBytes) {
    const auto& server = test::NginxServer::instance();
    net::RangeCache::configure({{}, 0});  // every range from the server
    const auto bytes = whole_file(test::data_dir() / kTile);
    // (a query makes the URL this test's own: a file registered by an earlier test would come open)
    const std::string url = server.url(kTile) + "?from_start=1";
    auto before = net::HttpClient::shared().stats().requests;
    const auto [file, first] = RemoteFile::open_from_start(url, 10000).get();
    EXPECT_EQ(net::HttpClient::shared().stats().requests - before, 1u);
    EXPECT_EQ(file->size(), bytes.size());
    ASSERT_EQ(first.size(), 10000u);
    EXPECT_TRUE(std::equal(first.begin(), first.end(), bytes.begin()));
    ASSERT_EQ(file->head().size(), RemoteFile::kEdge);
    EXPECT_TRUE(std::equal(file->head().begin(), file->head().end(), bytes.begin()));
    EXPECT_TRUE(file->tail().empty());
    std::vector<std::uint8_t> end(8);
    file->read(bytes.size() - 8, end);
    EXPECT_TRUE(std::equal(end.begin(), end.end(), bytes.end() - 8)) << "a read past the first bytes";

    before = net::HttpClient::shared().stats().requests;
    const auto [again, nothing] = RemoteFile::open_from_start(url, 10000).get();
    EXPECT_EQ(again, file);
    EXPECT_TRUE(nothing.empty());
    EXPECT_EQ(RemoteFile::open(url), file);
    EXPECT_EQ(net::HttpClient::shared().stats().requests - before, 0u);

    EXPECT_EQ(RemoteFile::open_from_start(server.url(kTile) + "?from_start=2", bytes.size() + 100).get().first, bytes);
    auto missing = RemoteFile::open_from_start(server.url("surveys/missing.json"), 10000);
    EXPECT_THROW(missing.get(), Error);
    EXPECT_THROW(RemoteFile::open(server.url("surveys/missing.json")), Error) << "its failure reported again";
}

TEST(RemoteFile, TlsPeersAreVerified) {
    try {
        io::File::open(test::NginxServer::instance().https_url(kTile));
        FAIL() << "a certificate of an unknown CA was accepted";
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find("certificate"), std::string::npos) << e.what();
    }
}

TEST(RemoteFile, AFileChangedDuringTheSessionIsAnError) {
    const auto& server = test::NginxServer::instance();
    const fs::path local = server.lists_dir() / "changing.bin";
    std::vector<char> content(100000, 'a');  // (a file of a few KiB is read whole when opened)
    std::ofstream(local, std::ios::binary).write(content.data(), static_cast<std::streamsize>(content.size()));
    const auto f = io::File::open(server.url("lists/changing.bin"));
    std::vector<std::uint8_t> got(100);
    f.read_exact(9000, got);
    EXPECT_EQ(got[0], 'a');
    std::fill(content.begin(), content.end(), 'b');
    std::ofstream(local, std::ios::binary).write(content.data(), static_cast<std::streamsize>(content.size()));
    fs::last_write_time(local, fs::last_write_time(local) + std::chrono::seconds(10));  // a new ETag
    try {
        f.read_exact(9100, got);  // (9000 again would be the old version's bytes, from the range cache)
        FAIL() << "bytes of the new version were mixed in";
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find("changed on the server"), std::string::npos) << e.what();
    }
}

// A server that sends no validator (no ETag, no Last-Modified) switches to another file of
// another size between reads: the size its Content-Range gives tells it, and the read fails.
TEST(RemoteFile, AServerWithoutValidatorSwitchingFilesIsAnError) {
    test::FaultServer server({});
    std::atomic<std::size_t> size{100000};  // (a file of a few KiB is read whole when opened)
    server.respond = [&](const std::string& head) {
        const auto range = head.substr(head.find("Range: bytes=") + 13);
        const std::uint64_t first = std::stoull(range), last = std::stoull(range.substr(range.find('-') + 1));
        const std::uint64_t end = std::min<std::uint64_t>(last + 1, size);
        const std::string body(end - first, static_cast<char>(size / 1000));
        return std::make_shared<const std::string>(
            "HTTP/1.1 206 Partial Content\r\nContent-Range: bytes " + std::to_string(first) + "-" +
            std::to_string(end - 1) + "/" + std::to_string(size) +
            "\r\nContent-Length: " + std::to_string(body.size()) + "\r\n\r\n" + body);
    };
    const auto f = RemoteFile::open(server.url());
    EXPECT_EQ(f->size(), 100000u);
    EXPECT_EQ(f->validator(), "");
    std::vector<std::uint8_t> got(100);
    f->read(5000, got);
    EXPECT_EQ(got[0], 100);
    size = 120000;  // another file
    try {
        f->read(5100, got);
        FAIL() << "bytes of another file were read";
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find("the file changed on the server during this session (its size was 100000 "
                                             "bytes, now 120000)"),
                  std::string::npos)
            << e.what();
    }
    EXPECT_EQ(server.requests(), 4);  // head, tail, the two reads: no retry
}

// Redirects (301, 302, 307, 308) of ranged requests are followed; the file's later requests go
// where they led, and a 403 there (a signed URL that expired) asks the file's own URL again, once.
TEST(RemoteFile, RedirectsAreKeptPerFileAndResolvedAgainWhenTheyExpire) {
    std::vector<std::uint8_t> data(100000);
    for (std::size_t i = 0; i < data.size(); ++i) data[i] = static_cast<std::uint8_t>(i * 7);
    net::RangeCache::configure({{}, 0});
    for (const int status : {301, 302, 307, 308}) {
        test::FaultServer origin(data), signed_host(data);
        set_allowed_origins(parse_allowed_origins(signed_host.url()));
        origin.redirect_to = signed_host.url();
        origin.redirect_status = status;
        origin.inject(test::Fault::Redirect, 1000);
        const auto f = RemoteFile::open(origin.url());  // head (redirected), tail (straight there)
        EXPECT_EQ(origin.requests(), 1) << status;
        EXPECT_EQ(signed_host.requests(), 2) << status;
        std::vector<std::uint8_t> got(1000);
        f->read(5000, got);
        EXPECT_TRUE(std::equal(got.begin(), got.end(), data.begin() + 5000)) << status;
        EXPECT_EQ(origin.requests(), 1) << status;
        signed_host.inject(test::Fault::Forbidden, 1);  // expired: resolved again from the origin
        f->read(9000, got);
        EXPECT_TRUE(std::equal(got.begin(), got.end(), data.begin() + 9000)) << status;
        EXPECT_EQ(origin.requests(), 2) << status;
        signed_host.inject(test::Fault::Forbidden, 2);  // still refused after resolving again: the error
        try {
            f->read(20000, got);
            FAIL() << "a 403 after resolving again was not an error";
        } catch (const Error& e) {
            EXPECT_NE(std::string(e.what()).find("403, error AccessDenied"), std::string::npos) << e.what();
        }
        EXPECT_EQ(origin.requests(), 3) << status;
    }
    set_allowed_origins({});
}

}  // namespace
}  // namespace lidarscout::net
