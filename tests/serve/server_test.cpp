// `lidarscout serve`'s API over a real survey on a free loopback port: the dataset's info, tiles,
// cells, quantized chunk points (every point within the lattice's half step of where the grid has
// it), heightmap patches, gzip with ETags and 304s; and the refusals: paths with "..", percent-
// encoding or a backslash, a dataset index out of range, a symbolic link in the page's folder,
// bad or too many cells, a missing or wrong token, methods other than GET, CORS only when asked.
#include <gtest/gtest.h>

#include <cstring>
#include <filesystem>
#include <fstream>

#include <nlohmann/json.hpp>

#include "serve/encoding.hpp"
#include "serve/gzip.hpp"
#include "serve_fixture.hpp"
#include "temp_dir_fixture.hpp"

namespace lidarscout::test {
namespace {

std::string woodford() { return (surveys_dir() / "ky-woodford-county").string(); }

const httplib::Headers kGzip = {{"Accept-Encoding", "gzip"}};

template <typename T>
T read_at(const std::string& s, std::size_t offset) {
    T v;
    std::memcpy(&v, s.data() + offset, sizeof v);
    return v;
}

TEST(ServeApi, InfoAndTilesDescribeTheSurvey) {
    RunningServer s({woodford()});
    auto c = s.client();
    s.survey->wait_loaded();
    const auto info = c.Get("/api/info");
    ASSERT_TRUE(info);
    ASSERT_EQ(info->status, 200);
    const auto j = nlohmann::json::parse(info->body).at("datasets").at(0);
    EXPECT_EQ(j.at("tiles"), 1);
    EXPECT_EQ(j.at("point_count"), s.survey->dataset().point_count);
    EXPECT_TRUE(j.at("loading").at("finished").get<bool>());
    EXPECT_EQ(j.at("bounds_m").size(), 6u);
    const auto tiles = nlohmann::json::parse(c.Get("/api/d/0/tiles")->body);
    EXPECT_EQ(tiles.at("names").at(0), "5205000_3900000.laz");  // a file name, never a path
    EXPECT_EQ(tiles.at("boxes_dm").size(), 6u);
}

TEST(ServeApi, ChunkPointsComeBackOnTheirLattice) {
    RunningServer s({woodford()});
    s.survey->wait_loaded();
    auto c = s.client();
    const auto cells = c.Get("/api/d/0/cells")->body;
    const auto n = read_at<std::uint32_t>(cells, 0);
    ASSERT_GT(n, 0u);
    std::string list;
    std::uint64_t listed = 0;
    for (std::uint32_t i = 0; i < n; ++i) {
        list += (i ? ";" : "") + std::to_string(read_at<std::int32_t>(cells, 4 + 12 * i)) + "," +
                std::to_string(read_at<std::int32_t>(cells, 8 + 12 * i));
        listed += read_at<std::uint32_t>(cells, 12 + 12 * i);
    }
    EXPECT_EQ(listed, s.survey->grid().size());
    const auto res = c.Get("/api/d/0/points?cells=" + list);
    ASSERT_EQ(res->status, 200);
    const std::string& body = res->body;
    std::size_t offset = 0, points = 0;
    const double size = s.survey->grid().patch_size(), half_xy = 0.5 * size / 2047 + 1e-3;
    while (offset < body.size()) {
        const CellKey cell{read_at<std::int32_t>(body, offset), read_at<std::int32_t>(body, offset + 4)};
        const auto count = read_at<std::uint32_t>(body, offset + 8);
        const float z0 = read_at<float>(body, offset + 12), z1 = read_at<float>(body, offset + 16);
        const auto expected = s.survey->grid().points_in(cell);
        ASSERT_EQ(count, expected.size());
        for (std::uint32_t i = 0; i < count; ++i) {
            const auto p = serve::decode_position(read_at<std::uint32_t>(body, offset + 24 + 4 * i), size, z0, z1);
            EXPECT_NEAR(p.dx, expected[i].dx, half_xy);
            EXPECT_NEAR(p.dy, expected[i].dy, half_xy);
            EXPECT_NEAR(p.z, expected[i].z, 0.5 * (z1 - z0) / 1023 + 1e-3);
        }
        offset += 24 + count * 10;  // 4 bytes of position, 3 of colour, 1 class, 2 intensity
        points += count;
    }
    EXPECT_EQ(offset, body.size());
    EXPECT_EQ(points, listed);
}

TEST(ServeApi, HeightmapsOnceLoaded) {
    RunningServer s({woodford()});
    s.survey->wait_loaded();
    const auto cell = s.survey->grid().cells().front();
    const auto res = s.client().Get("/api/d/0/heightmaps?cells=" + std::to_string(cell.ix) + "," +
                                    std::to_string(cell.iy));
    ASSERT_EQ(res->status, 200);
    ASSERT_GE(res->body.size(), 32u);
    const auto size = read_at<std::uint16_t>(res->body, 8);
    const bool colours = read_at<std::uint16_t>(res->body, 10) & 1;
    EXPECT_EQ(res->body.size(), 32u + size * size * (2u + (colours ? 3u : 0u)));
}

TEST(ServeApi, GzipEtagAndNotModified) {
    RunningServer s({woodford()});
    s.survey->wait_loaded();
    auto c = s.client();
    const auto plain = c.Get("/api/d/0/tiles");
    const auto packed = c.Get("/api/d/0/tiles", kGzip);
    ASSERT_EQ(packed->status, 200);
    EXPECT_EQ(packed->get_header_value("Content-Encoding"), "gzip");
    EXPECT_EQ(plain->get_header_value("Content-Encoding"), "");
    EXPECT_EQ(serve::gunzip(packed->body), plain->body);  // compressed once, not twice
    const std::string etag = packed->get_header_value("ETag");
    ASSERT_FALSE(etag.empty());
    EXPECT_FALSE(packed->get_header_value("Cache-Control").empty());
    const auto again = c.Get("/api/d/0/tiles", {{"If-None-Match", etag}});
    EXPECT_EQ(again->status, 304);
    EXPECT_TRUE(again->body.empty());
    const auto page = c.Get("/", kGzip);
    ASSERT_EQ(page->status, 200);
    EXPECT_NE(serve::gunzip(page->body).find("<canvas"), std::string::npos);
}

TEST(ServeSecurity, PathTricksAreRefused) {
    RunningServer s({woodford()});
    auto c = s.client();
    c.set_url_encode(false);  // the paths go out byte for byte
    for (const char* path : {"/../../etc/passwd", "/api/d/0/../../../etc/passwd", "/%2e%2e/%2e%2e/etc/passwd",
                             "/%2E%2E%2Fetc%2Fpasswd", "/api/d/0/cells%00", "/..%5c..%5cetc%5cpasswd",
                             "/\\..\\etc\\passwd"}) {
        const auto res = c.Get(path);
        ASSERT_TRUE(res) << path;
        EXPECT_EQ(res->status, 400) << path;
    }
    for (const char* path : {"/etc/passwd", "/api/d/1/cells", "/api/d/99999/cells", "/README.md", "/web/index.html"}) {
        const auto res = c.Get(path);
        ASSERT_TRUE(res) << path;
        EXPECT_EQ(res->status, 404) << path;
        EXPECT_EQ(res->body.find("root:"), std::string::npos);
    }
    EXPECT_EQ(c.Post("/api/info", "x", "text/plain")->status, 405);
}

TEST(ServeSecurity, CellListsAreBounded) {
    RunningServer s({woodford()});
    auto c = s.client();
    std::string many;
    for (int i = 0; i <= static_cast<int>(serve::kMaxCellsPerRequest); ++i) {
        many += (i ? ";" : "") + std::to_string(i) + ",0";
    }
    for (const std::string& cells : {many, std::string("1"), std::string("a,b"), std::string(""),
                                     std::string("99999999999,0")}) {
        const auto res = c.Get("/api/d/0/points?cells=" + cells);
        ASSERT_TRUE(res);
        EXPECT_EQ(res->status, 400) << cells.substr(0, 40);
    }
    EXPECT_THROW(serve::parse_cells(many), Error);
    EXPECT_EQ(serve::parse_cells("1,2;-3,4").size(), 2u);
}

class ServeWebFolder : public TempDirTest {};

TEST_F(ServeWebFolder, SymbolicLinksAreNotServed) {
    std::ofstream(dir / "index.html") << "<canvas>";
    std::ofstream(dir / "secret.txt") << "secret";
    std::filesystem::create_symlink("/etc/passwd", dir / "passwd.js");
    std::filesystem::create_symlink(dir / "secret.txt", dir / "secret.js");
    serve::ServerOptions o;
    o.web_dir = dir.string();
    RunningServer s({woodford()}, o);
    auto c = s.client();
    EXPECT_EQ(c.Get("/")->status, 200);
    EXPECT_EQ(c.Get("/passwd.js")->status, 404);
    EXPECT_EQ(c.Get("/secret.js")->status, 404);
    EXPECT_EQ(c.Get("/secret.txt")->status, 404);
}

TEST(ServeSecurity, TokenRefusedUnlessGiven) {
    serve::ServerOptions o;
    o.token = "s3cret-token";
    RunningServer s({woodford()}, o);
    auto c = s.client();
    EXPECT_EQ(c.Get("/api/info")->status, 403);
    EXPECT_EQ(c.Get("/api/info?token=wrong-token")->status, 403);
    EXPECT_EQ(c.Get("/api/info?token=s3cret-toke")->status, 403);
    EXPECT_EQ(c.Get("/api/d/0/tiles?token=s3cret-token")->status, 200);
    EXPECT_EQ(c.Get("/api/info", {{"Authorization", "Bearer s3cret-token"}})->status, 200);
    EXPECT_EQ(c.Get("/api/info", {{"Authorization", "Bearer nope"}})->status, 403);
    EXPECT_EQ(c.Get("/api/d/0/cells")->status, 403);
    EXPECT_EQ(c.Get("/api/d/0/points?cells=0,0")->status, 403);
    EXPECT_EQ(c.Get("/?token=s3cret-token")->status, 200);  // the page (no data) reads the token from its URL
    EXPECT_NE(s.server->url().find("?token=s3cret-token"), std::string::npos);
}

TEST(ServeSecurity, CorsOnlyWhenAsked) {
    {
        RunningServer s({woodford()});
        EXPECT_FALSE(s.client().Get("/api/info")->has_header("Access-Control-Allow-Origin"));
    }
    serve::ServerOptions o;
    o.cors_origin = "https://example.org";
    RunningServer s({woodford()}, o);
    EXPECT_EQ(s.client().Get("/api/info")->get_header_value("Access-Control-Allow-Origin"), "https://example.org");
}

TEST(ServeListen, AddressesAndTheTokenRule) {
    EXPECT_EQ(serve::parse_listen_address("127.0.0.1:8080").port, 8080);
    EXPECT_EQ(serve::parse_listen_address(":0").host, "127.0.0.1");
    EXPECT_EQ(serve::parse_listen_address("[::1]:9").host, "::1");
    for (const char* bad : {"127.0.0.1", "127.0.0.1:99999", "example.org:80", "1.2.3:80", "127.0.0.1:-1"}) {
        EXPECT_THROW(serve::parse_listen_address(bad), Error) << bad;
    }
    EXPECT_TRUE(serve::is_loopback("127.0.0.1"));
    EXPECT_TRUE(serve::is_loopback("127.1.2.3"));
    EXPECT_TRUE(serve::is_loopback("::1"));
    EXPECT_FALSE(serve::is_loopback("0.0.0.0"));
    EXPECT_FALSE(serve::is_loopback("192.168.1.2"));
    EXPECT_THROW(serve::check_access_rule(serve::parse_listen_address("0.0.0.0:0"), ""), Error);
    EXPECT_THROW(serve::check_access_rule(serve::parse_listen_address("0.0.0.0:0"), "short"), Error);
    EXPECT_THROW(serve::check_access_rule(serve::parse_listen_address("0.0.0.0:0"), "has space in"), Error);
    EXPECT_NO_THROW(serve::check_access_rule(serve::parse_listen_address("0.0.0.0:0"), "long-enough-token"));
    EXPECT_NO_THROW(serve::check_access_rule(serve::parse_listen_address("127.0.0.1:0"), ""));
    EXPECT_TRUE(serve::same_token("abcdefgh", "abcdefgh"));
    EXPECT_FALSE(serve::same_token("abcdefgx", "abcdefgh"));
    EXPECT_FALSE(serve::same_token("abcdefghi", "abcdefgh"));
    EXPECT_FALSE(serve::same_token("", "abcdefgh"));
}

TEST(ServeCommand, PrintsItsUrlFirstAndServes) {
    ServeChild child("'" + woodford() + "'");
    const std::string url = child.url();
    ASSERT_EQ(url.rfind("http://127.0.0.1:", 0), 0u) << url;
    const int port = std::stoi(url.substr(std::strlen("http://127.0.0.1:")));
    httplib::Client c("127.0.0.1", port);
    const auto res = c.Get("/api/info");
    ASSERT_TRUE(res);
    EXPECT_EQ(res->status, 200);
}

TEST(ServeCommand, NonLoopbackWithoutTokenIsOneLine) {
    const auto err = std::filesystem::temp_directory_path() / ("serve_refused_" + std::to_string(::getpid()));
    const int status = std::system(("'" + std::string(LIDARSCOUT_CLI) + "' serve '" + woodford() +
                                    "' --listen 0.0.0.0:0 >/dev/null 2>'" + err.string() + "'").c_str());
    std::ifstream in(err);
    const std::string text{std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
    std::filesystem::remove(err);
    EXPECT_NE(status, 0);
    EXPECT_NE(text.find("needs --token"), std::string::npos) << text;
    EXPECT_EQ(std::count(text.begin(), text.end(), '\n'), 1) << text;
}

}  // namespace
}  // namespace lidarscout::test
