// A request's client seen to leave (serve/client_link.hpp) and the server's expensive work given up
// for it, counted in /api/stats: a connection found by its two ends and its peer's close seen; a
// tile not decoded and heightmaps no longer built for a gone client; and end to end, 27 level
// requests whose client closes its connections leave most tiles undecoded. And the listening
// socket's backlog widened (httplib's 5 dropped connections of clients that open many at once).
#include <gtest/gtest.h>

#include <arpa/inet.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <nlohmann/json.hpp>

#include "core/error.hpp"
#include "delay_proxy.hpp"
#include "serve/client_link.hpp"
#include "serve/encoding.hpp"
#include "serve_fixture.hpp"

namespace lidarscout::test {
namespace {

std::string woodford() { return (surveys_dir() / "ky-woodford-county").string(); }
std::string jmo335() { return (surveys_dir() / "ky-jmo335-eastern-kentucky").string(); }

int port_of(int fd, bool peer) {
    sockaddr_in a{};
    socklen_t len = sizeof a;
    if (peer) ::getpeername(fd, reinterpret_cast<sockaddr*>(&a), &len);
    else ::getsockname(fd, reinterpret_cast<sockaddr*>(&a), &len);
    return ntohs(a.sin_port);
}

TEST(ClientLink, ConnectionFoundByItsEndsAndItsCloseSeen) {
    int port = 0;
    const int listener = delay_proxy_detail::loopback_listener(port);
    ASSERT_GE(listener, 0);
    const int client = delay_proxy_detail::connect_loopback(port);
    ASSERT_GE(client, 0);
    const int served = ::accept(listener, nullptr, nullptr);
    ASSERT_GE(served, 0);
    const serve::ConnectionEnds ends{"127.0.0.1", port_of(served, false), "127.0.0.1", port_of(served, true)};
    EXPECT_EQ(serve::find_connection(ends), served);  // (not the client's end, which has the ports swapped)
    EXPECT_EQ(serve::find_connection({"127.0.0.1", ends.local_port, "127.0.0.1", 1}), -1);
    EXPECT_TRUE(serve::peer_connected(served));
    ASSERT_EQ(::send(client, "GET", 3, 0), 3);  // unread bytes (a pipelined request): still there
    EXPECT_TRUE(serve::peer_connected(served));
    serve::ClientLink link(ends);
    EXPECT_FALSE(link.gone());
    ::close(client);
    EXPECT_FALSE(serve::peer_connected(served));
    EXPECT_TRUE(link.gone());
    ::close(served);
    ::close(listener);
    EXPECT_TRUE(serve::ClientLink(ends).gone());  // no such socket any more: gone
}

// Connections to `port` that complete (SYN answered) while nothing accepts them, of `n` tried at once.
int completed_connections(int port, int n) {
    std::vector<pollfd> fds;
    for (int k = 0; k < n; ++k) {
        const int fd = ::socket(AF_INET, SOCK_STREAM | SOCK_NONBLOCK, 0);
        sockaddr_in a{};
        a.sin_family = AF_INET;
        a.sin_port = htons(static_cast<std::uint16_t>(port));
        a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
        ::connect(fd, reinterpret_cast<sockaddr*>(&a), sizeof a);
        fds.push_back({fd, POLLOUT, 0});
    }
    int done = 0;  // (polled until a look finds no more: those left wait for a second SYN)
    while (!fds.empty() && ::poll(fds.data(), fds.size(), 300) > 0) {
        for (auto it = fds.begin(); it != fds.end();) {
            if (!it->revents) {
                ++it;
                continue;
            }
            int error = 0;
            socklen_t len = sizeof error;
            done += ::getsockopt(it->fd, SOL_SOCKET, SO_ERROR, &error, &len) == 0 && !error;
            ::close(it->fd);
            it = fds.erase(it);
        }
    }
    for (const auto& p : fds) ::close(p.fd);
    return done;
}

TEST(ClientLink, BacklogWidened) {
    int port = 0;
    const int listener = delay_proxy_detail::loopback_listener(port);
    ASSERT_EQ(::listen(listener, 1), 0);  // as narrow as can be
    EXPECT_LE(completed_connections(port, 16), 3);
    EXPECT_TRUE(serve::widen_backlog(port, 64));
    EXPECT_EQ(completed_connections(port, 16), 16);
    EXPECT_FALSE(serve::widen_backlog(port_of(listener, false) == 1 ? 2 : 1, 64));  // no listener there
    ::close(listener);
}

TEST(ServeCancel, NoTileDecodedForAGoneClient) {
    RunningServer s({woodford()});
    EXPECT_THROW(s.survey->level(0, 0, serve::kAllAttributes, [] { return true; }), Error);
    EXPECT_EQ(s.survey->tiles_decoded(), 0u);
    EXPECT_EQ(s.survey->cancelled(), 1u);
    s.survey->level(0, 0, serve::kAllAttributes, [] { return false; });  // and one for a client still there
    EXPECT_EQ(s.survey->tiles_decoded(), 1u);
}

TEST(ServeCancel, HeightmapsStopWhenTheClientGoes) {
    RunningServer s({jmo335()});
    s.survey->wait_loaded();
    const auto cells = s.survey->grid().cells();
    ASSERT_GT(cells.size(), serve::kHeightmapCellsPerStep);
    int looks = 0;
    const auto gone_after_one_step = [&] { return ++looks > 1; };
    EXPECT_THROW(s.survey->heightmaps(cells, false, 1, false, gone_after_one_step), Error);
    EXPECT_EQ(looks, 2);
    EXPECT_LE(s.survey->heightmaps_built(), serve::kHeightmapCellsPerStep);  // one step's, not all of them
    EXPECT_EQ(s.survey->cancelled(), 1u);
    ASSERT_TRUE(s.survey->heightmaps(cells, false, 1, false, [] { return false; }));
    EXPECT_GT(s.survey->heightmaps_built(), serve::kHeightmapCellsPerStep + 1);  // a client still there: all
}

nlohmann::json stats(httplib::Client& c) {
    const auto res = c.Get("/api/stats");
    return res && res->status == 200 ? nlohmann::json::parse(res->body) : nlohmann::json{};
}

std::uint64_t count(const nlohmann::json& stats, const char* what) {
    return stats.at("datasets").at(0).at(what).get<std::uint64_t>();
}

// 27 requests for levels of ky-jmo335's 9 tiles with three sets of attributes (each its own
// decoding), each on its own connection, sent one after another once the last has reached the
// server; then the client closes them all. Finishing them would decode a tile 27 times; after the
// close, no more than the two decoding slots held then (and one taken between the look and the
// close) are decoded, and every other request still queued is given up.
TEST(ServeCancel, LevelsAskedByAClientThatLeavesAreNotDecoded) {
    RunningServer s({jmo335()});
    auto c = s.client();
    const char* attrs[] = {"rgb565,class", "class", "intensity,class"};  // what the page's modes ask for
    const int tiles = static_cast<int>(s.survey->dataset().tiles.size()), asked = 3 * tiles;
    ASSERT_EQ(tiles, 9);
    std::vector<int> sockets;
    for (int k = 0; k < asked; ++k) {
        const auto before = stats(c).at("requests").get<std::uint64_t>();
        const std::string request = "GET /api/d/0/tile/" + std::to_string(k % tiles) + "/level/0?attrs=" +
                                    attrs[k / tiles] + " HTTP/1.1\r\nHost: 127.0.0.1\r\n\r\n";
        sockets.push_back(delay_proxy_detail::connect_loopback(s.port));
        ASSERT_GE(sockets.back(), 0);
        ASSERT_EQ(::send(sockets.back(), request.data(), request.size(), 0), static_cast<ssize_t>(request.size()));
        // (until the server has taken it: this look and the request)
        for (int i = 0; i < 2000 && stats(c).at("requests").get<std::uint64_t>() < before + 2; ++i) ::usleep(1000);
    }
    const auto at_close = stats(c);
    for (const int fd : sockets) ::close(fd);
    const int queued = at_close.at("in_flight").get<int>() - 1;
    for (int i = 0; i < 10000 && stats(c).at("in_flight") != 1; ++i) ::usleep(2000);
    const auto after = stats(c);
    ASSERT_EQ(after.at("in_flight"), 1);
    const auto decoded = count(after, "tiles_decoded"), cancelled = count(after, "cancelled");
    std::printf("%d level requests, %d under way when their client left: %llu decodings (%llu before it left), "
                "%llu given up\n", asked, queued, static_cast<unsigned long long>(decoded),
                static_cast<unsigned long long>(count(at_close, "tiles_decoded")),
                static_cast<unsigned long long>(cancelled));
    EXPECT_GE(queued, asked / 2);  // (most of them: a decoding takes far longer than a request's arrival)
    EXPECT_LE(decoded, count(at_close, "tiles_decoded") + 3);
    EXPECT_GE(cancelled + 3, static_cast<std::uint64_t>(queued));
    EXPECT_LT(decoded, static_cast<std::uint64_t>(asked / 2));
}

}  // namespace
}  // namespace lidarscout::test
