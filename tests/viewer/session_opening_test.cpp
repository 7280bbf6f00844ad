// SessionOpening: a survey opened in the background gives the same tiles as open_dataset, with
// every footprint and the progress counted on the way and a running scheduler at the end; a
// large catalog opens its central tiles first as a preview whose chunk points are in before the
// rest is read, unless its items place every tile (it then opens at once, placed, with no
// preview, and every tile's chunk points still load); a paged catalog (the replica server's STAC API
// search, its last page held) opens its first pages as the preview (growing as pages arrive), whose chunk
// points load, before the last page is served; a path without tiles ends in the viewer's one-line error;
// an opening destroyed while it reads cancels without a hang.
#include <gtest/gtest.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <thread>

#include <nlohmann/json.hpp>

#include "core/error.hpp"
#include "dataset/catalog_writer.hpp"
#include "dataset/dataset.hpp"
#include "net/range_cache.hpp"
#include "net/remote_file.hpp"
#include "replica_server.hpp"
#include "test_data.hpp"
#include "viewer/session_opening.hpp"

namespace lidarscout::viewer {
namespace {

namespace fs = std::filesystem;

SessionOptions no_network() {
    SessionOptions o;
    o.scheduler.cnn = false;
    o.scheduler.full_res = false;
    return o;
}

TEST(SessionOpening, OpensASurveyWithItsFootprintsOnTheWay) {
    const auto folder = (test::surveys_dir() / "ky-jmo335-eastern-kentucky").string();
    const dataset::Dataset expected = dataset::open_dataset({folder});
    SessionOpening opening({folder}, no_network());
    Session session = opening.take();
    ASSERT_TRUE(session.open());
    EXPECT_TRUE(opening.finished());
    ASSERT_EQ(session.dataset->tiles.size(), expected.tiles.size());
    for (std::size_t i = 0; i < expected.tiles.size(); ++i) {
        EXPECT_EQ(session.dataset->tiles[i].tile.path(), expected.tiles[i].tile.path());
    }
    const OpeningProgress p = opening.progress();
    EXPECT_EQ(p.done, expected.tiles.size());
    EXPECT_EQ(p.total, expected.tiles.size());
    EXPECT_EQ(p.read, expected.tiles.size());
    EXPECT_TRUE(p.building);
    EXPECT_DOUBLE_EQ(p.extent.min_x, expected.bounds_m.min_x);
    EXPECT_DOUBLE_EQ(p.extent.max_y, expected.bounds_m.max_y);
    std::vector<dataset::Bounds> footprints;
    opening.footprints(footprints);
    EXPECT_EQ(footprints.size(), expected.tiles.size());
    opening.footprints(footprints);  // nothing new
    EXPECT_EQ(footprints.size(), expected.tiles.size());
    EXPECT_EQ(session.scheduler->stats().tiles, expected.tiles.size());
    EXPECT_THROW(opening.take(), Error);  // once only
}

// A catalog whose items place every tile opens at once, placed (dataset.hpp): no preview, its headers read
// by the scheduler's loader, every tile's chunk points loaded all the same.
TEST(SessionOpening, ACatalogThatPlacesEveryTileOpensAtOnceWithoutAPreview) {
    const auto folder = (test::surveys_dir() / "ky-jmo335-eastern-kentucky").string();
    const fs::path dir = fs::temp_directory_path() / ("lidarscout_opening_placed_" + std::to_string(::getpid()));
    fs::create_directories(dir);
    const std::string vpc = (dir / "ky.vpc").string();
    const dataset::Dataset eager = dataset::open_dataset({folder});
    dataset::write_catalog(eager, vpc);
    SessionOptions o = no_network();
    o.preview_above = 4;
    SessionOpening opening({vpc}, o);
    const Session session = opening.take();
    ASSERT_TRUE(session.open());
    EXPECT_TRUE(session.dataset->placed);
    EXPECT_EQ(opening.preview(), nullptr);
    EXPECT_EQ(session.dataset->tiles.size(), eager.tiles.size());
    const auto until = std::chrono::steady_clock::now() + std::chrono::seconds(60);
    const auto loaded = [&] { return session.scheduler->stats().tiles_loaded.done; };
    while (loaded() < eager.tiles.size() && std::chrono::steady_clock::now() < until) {
        std::this_thread::sleep_for(std::chrono::milliseconds(20));
    }
    EXPECT_EQ(session.scheduler->stats().tiles_loaded.done, eager.tiles.size());
    EXPECT_EQ(session.dataset->tiles_ready(), eager.tiles.size());
    EXPECT_EQ(session.scheduler->stats().chunk_points.done, eager.chunk_point_count);
    fs::remove_all(dir);
}

// A catalog whose items do not place every tile (one without pc:count here) opens its centre first.
TEST(SessionOpening, ALargeCatalogOpensItsCentreFirstAsAPreview) {
    const auto folder = (test::surveys_dir() / "ky-jmo335-eastern-kentucky").string();
    const fs::path dir = fs::temp_directory_path() / ("lidarscout_opening_vpc_" + std::to_string(::getpid()));
    fs::create_directories(dir);
    const std::string vpc = (dir / "ky.vpc").string();
    dataset::write_catalog(dataset::open_dataset({folder}), vpc);
    {
        auto catalog = nlohmann::json::parse(std::ifstream(vpc));
        catalog.at("features").back().at("properties").erase("pc:count");
        std::ofstream(vpc) << catalog.dump();
    }
    {
        SessionOpening small({vpc}, no_network());  // 9 items: no preview at the default size
        EXPECT_TRUE(small.take().open());
        EXPECT_EQ(small.preview(), nullptr);
    }
    SessionOptions o = no_network();
    o.preview_above = 4, o.preview_radius_m = 800, o.preview_wait_s = 60;
    const auto sources = dataset::find_tile_sources({vpc}).sources;
    const auto central =
        dataset::central_sources(sources, dataset::catalog_footprints(sources), o.preview_radius_m, o.preview_tiles);
    ASSERT_GE(central.size(), 2u);
    ASSERT_LT(central.size(), sources.size());
    SessionOpening opening({vpc}, o);
    const Session session = opening.take();
    ASSERT_TRUE(session.open());
    EXPECT_EQ(session.dataset->tiles.size(), sources.size());
    std::vector<dataset::Bounds> footprints;
    opening.footprints(footprints);
    EXPECT_EQ(footprints.size(), sources.size()) << "each tile's footprint once, its item's (a header read adds none)";
    const auto preview = opening.preview();
    ASSERT_NE(preview, nullptr);
    ASSERT_EQ(preview->dataset->tiles.size(), central.size());
    for (std::size_t i = 0; i < central.size(); ++i) {
        EXPECT_EQ(preview->dataset->tiles[i].tile.path(), central[i].path);
    }
    const SchedulerStats stats = preview->scheduler->stats();
    EXPECT_EQ(stats.tiles_loaded.done, stats.tiles_loaded.total) << "the rest opened before the preview's reads ended";
    EXPECT_EQ(stats.full_res.total, 0u) << "a preview decodes no tile";
    const auto until = std::chrono::steady_clock::now() + std::chrono::seconds(60);
    while (preview->scheduler->stats().heightmaps_linear == 0 && std::chrono::steady_clock::now() < until) {
        std::this_thread::sleep_for(std::chrono::milliseconds(20));
    }
    EXPECT_GT(preview->scheduler->stats().heightmaps_linear, 0u);
    fs::remove_all(dir);
}

// Waits until `done` holds (at most a minute: a bound against a hang, not a measure); whether it does.
template <typename Done>
bool wait_until(Done&& done) {
    const auto until = std::chrono::steady_clock::now() + std::chrono::seconds(60);
    while (!done() && std::chrono::steady_clock::now() < until) {
        std::this_thread::sleep_for(std::chrono::milliseconds(20));
    }
    return done();
}

// A STAC API search of 36 items in pages of 8, its last page held by the server until released: the first
// page opens as the preview, and again the first four pages when they are four times as many (unless that
// passes page_preview_most); the preview's tiles' chunk points load, every page's footprint but the last's
// is shown, and the opening is not finished, all while the last page waits; released, the whole catalog
// opens.
TEST(SessionOpening, APagedCatalogOpensItsFirstPagesWhileTheLastWaits) {
    net::RangeCache::configure({{}, 0});
    const fs::path dir = fs::temp_directory_path() / ("lidarscout_opening_pages_" + std::to_string(::getpid()));
    fs::remove_all(dir);
    const std::string tile = (test::surveys_dir() / "ky-jmo335-eastern-kentucky" / "N117E380.laz").string();
    const std::string cmd = std::string(LIDARSCOUT_CLI) + " synth replicate " + tile + " --grid 6x6 --virtual -o " +
                            (dir / "r").string() + " >/dev/null";
    ASSERT_EQ(std::system(cmd.c_str()), 0) << cmd;
    for (const auto& [most, shown] : {std::pair<std::size_t, std::size_t>{16, 8}, {4096, 32}}) {
        SCOPED_TRACE("page_preview_most " + std::to_string(most));
        net::RemoteFile::forget_all();
        test::ReplicaServer::Options so;
        so.hold_last_page = true;
        test::ReplicaServer server(dir / "r" / "replicate.json", so);
        SessionOptions o = no_network();
        o.preview_above = 4, o.page_preview_most = most;
        SessionOpening opening({server.url("search?limit=8")}, o);
        ASSERT_TRUE(wait_until([&] { return server.stats().at("held").get<int>() == 1; })) << "last page not asked";
        const auto preview = opening.preview();  // (the last one: the last page is asked after it opened)
        ASSERT_NE(preview, nullptr);
        EXPECT_EQ(preview->dataset->tiles.size(), shown);
        EXPECT_TRUE(preview->dataset->placed);
        const auto loaded = [&] { return preview->scheduler->stats().tiles_loaded.done; };
        EXPECT_TRUE(wait_until([&] { return loaded() == shown; })) << loaded() << " of " << shown << " tiles loaded";
        std::vector<dataset::Bounds> footprints;
        opening.footprints(footprints);
        EXPECT_EQ(footprints.size(), 32u);  // the four pages served
        EXPECT_EQ(server.stats().at("held").get<int>(), 1) << "the last page was served";
        EXPECT_FALSE(opening.finished());
        EXPECT_EQ(opening.preview(), preview);
        server.release();
        const Session session = opening.take();
        ASSERT_TRUE(session.open());
        EXPECT_EQ(session.dataset->tiles.size(), 36u);
        EXPECT_TRUE(session.dataset->placed);
        opening.footprints(footprints);
        EXPECT_EQ(footprints.size(), 36u);
    }
    fs::remove_all(dir);
}

TEST(SessionOpening, NoReadableTileIsTheViewersError) {
    const fs::path empty = fs::temp_directory_path() / ("lidarscout_opening_empty_" + std::to_string(::getpid()));
    fs::create_directories(empty);
    SessionOpening opening({empty.string()}, no_network());
    try {
        opening.take();
        ADD_FAILURE() << "an empty folder opened";
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find("no readable"), std::string::npos) << e.what();
    }
    fs::remove_all(empty);
}

TEST(SessionOpening, DestroyedWhileOpeningCancels) {
    const auto folder = (test::surveys_dir() / "ky-jmo335-eastern-kentucky").string();
    std::size_t cancelled = 0;  // openings destroyed before every file was tried
    for (int i = 0; i < 5; ++i) {
        SessionOpening opening({folder, folder, folder}, no_network());
        std::this_thread::sleep_for(std::chrono::milliseconds(i * 5));
        const OpeningProgress p = opening.progress();
        cancelled += p.total == 0 || p.done < p.total;
    }  // each destructor cancels and joins (a destructor that hangs fails by the test's timeout)
    EXPECT_GE(cancelled, 1u) << "no opening was destroyed while opening: the test did not test cancelling";
}

}  // namespace
}  // namespace lidarscout::viewer
