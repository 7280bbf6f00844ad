// Point sets: chunk points of a cell (cell corner origin), counts and batches, grey for surveys
// without colour, a real tile decoded at full resolution (every point, inside its bounds, in
// metres), and the same tile in pieces (every point once, the nearest chunks first, a cap), a remote one's
// fetched a request a piece.
#include "viewer/point_sets.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <mutex>

#include "core/thread_pool.hpp"
#include "dataset/dataset.hpp"
#include "net/http_client.hpp"
#include "net/range_cache.hpp"
#include "nginx_server.hpp"
#include "test_data.hpp"

namespace lidarscout::viewer {
namespace {

constexpr double kOx = 700'000.0, kOy = 3'000'000.0;

TEST(ViewerPointSets, CellPointSetsAreRelativeToTheCellCorner) {
    lidarscout::PatchGrid grid(kOx, kOy);
    grid.add(kOx + 650.0, kOy + 10.0, 123.5, {1, 2, 3}, 77, 6, 0);
    const auto set = cell_point_set(grid, {1, 0});
    EXPECT_DOUBLE_EQ(set.origin_x, kOx + 640.0);
    EXPECT_DOUBLE_EQ(set.origin_y, kOy);
    ASSERT_EQ(set.points.size(), 1u);
    EXPECT_NEAR(set.points[0].dx, 10.0f, 1e-3);
    EXPECT_NEAR(set.points[0].dy, 10.0f, 1e-3);
    EXPECT_NEAR(set.origin_z + set.points[0].dz, 123.5, 1e-3);
    EXPECT_EQ(set.points[0].r, 1);
    EXPECT_EQ(set.points[0].intensity, 77);
    EXPECT_EQ(set.points[0].classification, 6);
    const auto batches = batches_of(std::span(&set, 1));
    ASSERT_EQ(batches.size(), 1u);
    EXPECT_EQ(batches[0].points.size(), 1u);
}

TEST(ViewerPointSets, CountsBatchesAndTheGreyOfUncolouredSurveys) {
    std::vector<PointSet> sets(2);
    sets[0].points.resize(2), sets[1].points.resize(3);
    sets[1].points[2].r = 9;
    EXPECT_EQ(point_count(sets), 5u);
    EXPECT_EQ(batches_of(sets).size(), 2u);
    paint_uncoloured(sets);
    for (const auto& set : sets) {
        for (const auto& p : set.points) {
            EXPECT_EQ(p.r, kUncolouredGrey);
            EXPECT_EQ(p.g, kUncolouredGrey);
            EXPECT_EQ(p.b, kUncolouredGrey);
        }
    }
}

TEST(ViewerPointSets, RealTileDecodedAtFullResolution) {
    const auto ds = dataset::open_dataset({(test::surveys_dir() / "ky-woodford-county").string()});
    ASSERT_EQ(ds.tiles.size(), 1u);
    const auto& t = ds.tiles[0];
    ThreadPool pool(2);
    std::uint64_t progressed = 0;
    const auto set = tile_point_set(t, ds.las_stride, pool, [&](std::uint64_t n) { progressed += n; });
    ASSERT_EQ(set.points.size(), t.tile.header.point_count);
    EXPECT_EQ(progressed, t.tile.header.point_count);
    EXPECT_EQ(tile_point_set_bytes(t), t.tile.header.point_count * sizeof(render::PointAttr));
    const auto& b = t.bounds_m;
    std::size_t outside = 0, coloured = 0;
    for (const auto& p : set.points) {
        const double x = set.origin_x + p.dx, y = set.origin_y + p.dy, z = set.origin_z + p.dz;
        outside += x < b.min_x - 0.01 || x > b.max_x + 0.01 || y < b.min_y - 0.01 || y > b.max_y + 0.01 ||
                   z < b.min_z - 0.01 || z > b.max_z + 0.01;
        coloured += (p.r | p.g | p.b) != 0;
    }
    EXPECT_EQ(outside, 0u);
    EXPECT_GT(coloured, set.points.size() / 2);  // the Kentucky tiles carry RGB
}

TEST(ViewerPointSets, PiecesHoldEveryPointOnceNearestChunksFirstAndStopAtTheCap) {
    const auto ds = dataset::open_dataset({(test::surveys_dir() / "ky-woodford-county").string()});
    ASSERT_EQ(ds.tiles.size(), 1u);
    const auto& t = ds.tiles[0];
    const auto& b = t.bounds_m;
    const auto order = [&](double x, double y, double) { return std::hypot(x - b.min_x, y - b.min_y); };
    ThreadPool pool(2);
    std::mutex m;
    std::vector<PointSet> pieces;
    const auto keep = [&](PointSet&& piece) {
        std::lock_guard lock(m);
        pieces.push_back(std::move(piece));
    };
    decode_tile_pieces(t, ds.las_stride, pool, order, 100'000, t.tile.header.point_count, keep);
    ASSERT_GE(pieces.size(), 3u);
    EXPECT_EQ(point_count(pieces), t.tile.header.point_count);
    // the piece nearest the south-west corner was cut from the chunks sorted first
    const auto mean_distance = [&](const PointSet& set) {
        double sum = 0;
        for (const auto& p : set.points) sum += order(set.origin_x + p.dx, set.origin_y + p.dy, 0);
        return sum / std::max<std::size_t>(set.points.size(), 1);
    };
    std::vector<double> distances;
    for (const auto& piece : pieces) distances.push_back(mean_distance(piece));
    EXPECT_LT(*std::min_element(distances.begin(), distances.end()),
              *std::max_element(distances.begin(), distances.end()));
    pieces.clear();
    decode_tile_pieces(t, ds.las_stride, pool, order, 100'000, 1, keep);  // the cap: still one piece
    ASSERT_EQ(pieces.size(), 1u);
    EXPECT_LT(pieces[0].points.size(), t.tile.header.point_count);
    EXPECT_GT(pieces[0].points.size(), 0u);
}

// A remote tile's pieces: its chunk points and each piece's chunks fetched together (a request or two each, not a
// round trip per chunk: 50 ms each had made a country's nearest tile wait 2.5 s), every point as the local tile's.
TEST(ViewerPointSets, ARemoteTilesPiecesAreARequestEach) {
    const char* const tile = "surveys/ky-woodford-county/5205000_3900000.laz";
    net::RangeCache::configure({{}, 0});  // every range from the server
    const auto local = dataset::open_dataset({(test::data_dir() / tile).string()});
    const auto remote = dataset::open_dataset({test::NginxServer::instance().url(tile) + "?pieces=1"});
    ASSERT_EQ(remote.tiles.size(), 1u);
    const auto& t = remote.tiles[0];
    const dataset::DecodeUnits units(t.tile);
    const auto order = [](double, double, double) { return 0.0; };
    ThreadPool pool(2);
    const auto decoded = [&](const dataset::DatasetTile& from, std::size_t& pieces) {
        std::mutex m;
        std::vector<std::pair<double, double>> xy;  // (sorted: pieces come in any order)
        pieces = 0;
        decode_tile_pieces(from, remote.las_stride, pool, order, 300'000, ~0ull, [&](PointSet&& piece) {
            std::lock_guard lock(m);
            ++pieces;
            for (const auto& p : piece.points) xy.emplace_back(piece.origin_x + p.dx, piece.origin_y + p.dy);
        });
        std::sort(xy.begin(), xy.end());
        return xy;
    };
    std::size_t pieces = 0, local_pieces = 0;
    const auto before = net::HttpClient::shared().stats().requests;
    const auto got = decoded(t, pieces);
    const auto requests = net::HttpClient::shared().stats().requests - before;
    EXPECT_EQ(got, decoded(local.tiles[0], local_pieces));
    EXPECT_EQ(got.size(), t.tile.header.point_count);
    ASSERT_GE(pieces, 3u);
    EXPECT_GT(units.size(), 2 * pieces);
    EXPECT_LE(requests, pieces + 2) << units.size() << " chunks in " << pieces << " pieces";
}

}  // namespace
}  // namespace lidarscout::viewer
