// `lidarscout serve`'s API over a real survey on a free loopback port: the dataset's info, tiles,
// cells, quantized chunk points (every point within the lattice's half step of where the grid has
// it), heightmap patches, gzip with ETags and 304s; and the refusals: paths with "..", percent-
// encoding or a backslash, a dataset index out of range, a symbolic link in the page's folder,
// bad or too many cells, a missing or wrong token, methods other than GET, CORS only when asked.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <tuple>
#include <filesystem>
#include <fstream>

#include <nlohmann/json.hpp>

#include "nn/heightmap_network.hpp"
#include "serve/encoding.hpp"
#include "viewer/point_sets.hpp"
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
    // the points of a cell as the lattice orders them (x, y, z rounded to a tenth of a step)
    const auto sorted = [&](std::vector<render::PointAttr> v) {
        std::sort(v.begin(), v.end(), [&](const auto& a, const auto& b) {
            return std::tuple(std::lround(a.dy / half_xy), std::lround(a.dx / half_xy), a.dz) <
                   std::tuple(std::lround(b.dy / half_xy), std::lround(b.dx / half_xy), b.dz);
        });
        return v;
    };
    while (offset < body.size()) {
        const auto block = serve::decode_block(body, offset, size);
        const auto expected = sorted(viewer::cell_point_set(s.survey->grid(), {block.ix, block.iy}).points);
        const auto got = sorted(block.points);
        ASSERT_EQ(got.size(), expected.size());
        float z0 = INFINITY, z1 = -INFINITY;
        for (const auto& p : expected) z0 = std::min(z0, p.dz), z1 = std::max(z1, p.dz);
        for (std::size_t i = 0; i < got.size(); ++i) {
            EXPECT_NEAR(got[i].dx, expected[i].dx, half_xy);
            EXPECT_NEAR(got[i].dy, expected[i].dy, half_xy);
            EXPECT_NEAR(got[i].dz, expected[i].dz, 0.5 * (z1 - z0) / 1023 + 1e-3);
            EXPECT_EQ(got[i].classification, expected[i].classification);
            EXPECT_EQ(got[i].intensity, expected[i].intensity);
        }
        points += got.size();
    }
    EXPECT_EQ(offset, body.size());
    EXPECT_EQ(points, listed);
}

TEST(ServeApi, LevelsOfDetailHoldEveryPointOnce) {
    RunningServer s({woodford()});
    auto c = s.client();
    std::uint64_t points = 0, without_attributes = 0, with = 0;
    for (int level = 0; level < serve::kLevels; ++level) {
        const auto all = c.Get("/api/d/0/tile/0/level/" + std::to_string(level));
        const auto bare = c.Get("/api/d/0/tile/0/level/" + std::to_string(level) + "?attrs=");
        ASSERT_EQ(all->status, 200);
        ASSERT_EQ(bare->status, 200);
        std::uint32_t blocks = 0;
        std::memcpy(&blocks, all->body.data() + 24, 4);
        std::size_t offset = 32;
        std::uint64_t n = 0;
        for (std::uint32_t b = 0; b < blocks; ++b) {
            n += serve::decode_block(all->body, offset, serve::kLodBlockM).points.size();
        }
        EXPECT_EQ(offset, all->body.size());
        EXPECT_EQ(bare->body.size() + 6 * n, all->body.size());  // 3 + 1 + 2 bytes of attributes a point
        points += n, with += all->body.size(), without_attributes += bare->body.size();
    }
    EXPECT_EQ(points, s.survey->dataset().tiles[0].tile.header.point_count);
    EXPECT_LT(without_attributes, 4 * points);  // positions: under 4 bytes a point before gzip
    EXPECT_EQ(c.Get("/api/d/0/tile/0/level/4")->status, 400);
    EXPECT_EQ(c.Get("/api/d/0/tile/1/level/0")->status, 400);
    EXPECT_EQ(c.Get("/api/d/0/tile/0/level/0?attrs=rgb,colour")->status, 400);
}

// A block on a coarse lattice (a level of detail's) comes back within half a step of every point, every
// point once, its colour within 5-6-5's rounding.
TEST(ServeEncoding, BlocksRoundTripOnTheirLattice) {
    std::vector<render::PointAttr> points;
    std::uint32_t seed = 7;
    const auto next = [&] { return (seed = seed * 1664525u + 1013904223u) >> 8; };
    for (int i = 0; i < 500; ++i) {
        render::PointAttr p;
        p.dx = static_cast<float>(next() % 12800) / 100.0f, p.dy = static_cast<float>(next() % 12800) / 100.0f;
        p.dz = 300.0f + static_cast<float>(next() % 4000) / 100.0f;
        p.r = static_cast<std::uint8_t>(next()), p.g = static_cast<std::uint8_t>(next());
        p.b = static_cast<std::uint8_t>(next()), p.classification = static_cast<std::uint8_t>(next() % 20);
        points.push_back(p);
    }
    const double step = 0.5;
    std::string body;
    serve::append_block(body, 3, -4, points, serve::kLodBlockM, serve::kRgb565 | serve::kClass, step);
    std::size_t offset = 0;
    const auto block = serve::decode_block(body, offset, serve::kLodBlockM);
    EXPECT_EQ(offset, body.size());
    EXPECT_EQ(block.ix, 3);
    EXPECT_EQ(block.iy, -4);
    ASSERT_EQ(block.points.size(), points.size());
    std::vector<bool> used(points.size());
    for (const auto& d : block.points) {  // its nearest original point not matched yet
        std::size_t best = points.size();
        double best_d = INFINITY;
        for (std::size_t i = 0; i < points.size(); ++i) {
            const double e = std::hypot(d.dx - points[i].dx, d.dy - points[i].dy, d.dz - points[i].dz);
            if (!used[i] && e < best_d) best = i, best_d = e;
        }
        ASSERT_LT(best, points.size());
        used[best] = true;
        EXPECT_LE(best_d, 0.5 * step * std::sqrt(3.0) + 1e-3);
        EXPECT_EQ(d.classification, points[best].classification);
        EXPECT_LE(points[best].r - d.r, 7);
        EXPECT_GE(points[best].r - d.r, 0);
        EXPECT_LE(points[best].g - d.g, 3);
        EXPECT_LE(points[best].b - d.b, 7);
    }
    // positions under 4 bytes a point before gzip even for random points (no neighbour near), 565 colour, class
    EXPECT_LT(body.size(), 28 + points.size() * (4 + 2 + 1));
    std::string bad = body.substr(0, body.size() - 1);
    offset = 0;
    EXPECT_THROW(serve::decode_block(bad, offset, serve::kLodBlockM), Error);
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
    const auto coarse = s.client().Get("/api/d/0/heightmaps?step=4&cells=" + std::to_string(cell.ix) + "," +
                                       std::to_string(cell.iy));
    ASSERT_EQ(coarse->status, 200);
    EXPECT_EQ(read_at<std::uint16_t>(coarse->body, 8), size / 4);
    EXPECT_FLOAT_EQ(read_at<float>(coarse->body, 20), 4 * read_at<float>(res->body, 20));  // texel_m
    EXPECT_EQ(coarse->body.size(), 32u + size * size / 16 * (2u + (colours ? 3u : 0u)));
    EXPECT_EQ(s.client().Get("/api/d/0/heightmaps?step=3&cells=0,0")->status, 400);
}

TEST(ServeApi, NetworkHeightmapsWithAModel) {
    RunningServer s({woodford()});
    s.survey->wait_loaded();
    const auto cell = s.survey->grid().cells().front();
    const std::string cells = std::to_string(cell.ix) + "," + std::to_string(cell.iy);
    auto c = s.client();
    EXPECT_EQ(c.Get("/api/d/0/heightmaps?method=cnn&cells=" + cells)->status, 400);  // no model: refused
    EXPECT_EQ(c.Get("/api/d/0/heightmaps?method=bicubic&cells=" + cells)->status, 400);
    s.survey->set_model(nn::default_model_path());
    const auto cnn = c.Get("/api/d/0/heightmaps?method=cnn&cells=" + cells);
    const auto linear = c.Get("/api/d/0/heightmaps?method=linear&cells=" + cells);
    ASSERT_EQ(cnn->status, 200);
    ASSERT_EQ(linear->status, 200);
    ASSERT_EQ(cnn->body.size(), linear->body.size());  // the same patch, texels and colours
    EXPECT_NE(cnn->body, linear->body);                 // by another method
    EXPECT_TRUE(nlohmann::json::parse(c.Get("/api/info")->body)["datasets"][0]["cnn"].get<bool>());
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
