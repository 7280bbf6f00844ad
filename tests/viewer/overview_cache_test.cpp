// The viewer's overview cache (viewer/overview_cache.hpp), through the replica server: the first open of a
// remote catalog keeps a sidecar written from what it read (a few requests more at most); the second open
// places every tile and takes every chunk point from it, asking the tiles for nothing; a tile changed on the
// server since is named and read itself; a damaged cached sidecar is named, ignored and written again; a
// bound below the sidecar, or a folder that cannot be made, keeps nothing and says so in one line.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <memory>
#include <string>

#include <nlohmann/json.hpp>

#include "core/error.hpp"
#include "dataset/dataset.hpp"
#include "dataset/overview_sidecar.hpp"
#include "io/file.hpp"
#include "net/range_cache.hpp"
#include "net/remote_file.hpp"
#include "replica_server.hpp"
#include "test_data.hpp"
#include "viewer/overview_cache.hpp"
#include "viewer/session_opening.hpp"
#include "wait_until.hpp"

namespace lidarscout::viewer {
namespace {

namespace fs = std::filesystem;

fs::path fresh_dir(const std::string& name) {
    const fs::path d = fs::temp_directory_path() / ("lidarscout_ovcache_" + name + "_" + std::to_string(::getpid()));
    fs::remove_all(d);
    fs::create_directories(d);
    return d;
}

// A 6 x 6 virtual replica of a ky-jmo335 tile in `dir`/r; its manifest.
fs::path replica(const fs::path& dir) {
    const std::string tile = (test::surveys_dir() / "ky-jmo335-eastern-kentucky" / "N117E379.laz").string();
    const std::string cmd = std::string(LIDARSCOUT_CLI) + " synth replicate " + tile + " --grid 6x6 --virtual -o " +
                            (dir / "r").string() + " >/dev/null";
    EXPECT_EQ(std::system(cmd.c_str()), 0);
    return dir / "r" / "replicate.json";
}

double tile_requests(const nlohmann::json& stats) {
    const auto& k = stats.at("kinds");
    return k.at("tile").at("requests").get<double>() + k.at("tile_head").at("requests").get<double>();
}

// `paths` opened as the viewer opens them, with the cache in `folder` (no network, no full resolution), its
// chunk points all loaded; as a new process would (no remote file open yet).
struct Opened {
    Opened(const std::vector<std::string>& paths, const fs::path& folder, std::uint64_t bound = 1ull << 30) {
        net::RemoteFile::forget_all();
        SessionOptions o;
        o.scheduler.cnn = false, o.scheduler.full_res = false;
        o.overview_cache = cache = std::make_shared<OverviewCache>(paths, OverviewCacheSettings{folder, bound});
        SessionOpening opening(paths, o);
        try {
            session = opening.take();
        } catch (const Error& e) {
            ADD_FAILURE() << "opening " << paths.size() << " paths: " << e.what();
            return;
        }
        const auto loaded = [&] {
            const auto s = session.scheduler->stats().tiles_loaded;
            return s.done >= s.total;
        };
        EXPECT_TRUE(test::wait_until(loaded));
    }
    // Writes the sidecar (when due); whether it was written.
    bool write() {
        cache->write_when_loaded(*session.dataset, true);
        return cache->wait();
    }
    std::size_t from_sidecar() const {
        std::size_t n = 0;
        for (const auto& t : session.dataset->tiles) n += t.tile.file && t.tile.file->overview ? 1 : 0;
        return n;
    }
    std::shared_ptr<OverviewCache> cache;
    Session session;
};

TEST(OverviewCache, TheSecondOpenAsksTheTilesForNothingAndAChangedTileIsNamed) {
    net::RangeCache::configure({{}, 0});
    const fs::path dir = fresh_dir("replica");
    const fs::path manifest = replica(dir);
    const fs::path folder = dir / "cache";
    int port = 0;
    std::vector<std::string> paths;
    std::uint64_t chunk_points = 0;
    {
        test::ReplicaServer server(manifest);
        port = server.port();
        paths = {server.catalog_url()};
        auto first = std::make_unique<Opened>(paths, folder);
        ASSERT_TRUE(first->session.open());
        const double read = tile_requests(server.stats(true));
        chunk_points = first->session.scheduler->stats().chunk_points.done;
        ASSERT_GT(chunk_points, 36u);
        EXPECT_EQ(first->from_sidecar(), 0u);
        EXPECT_TRUE(first->write());
        EXPECT_EQ(first->cache->take_note(), "");
        ASSERT_TRUE(fs::is_regular_file(first->cache->file()));
        first.reset();  // (nothing of the first session reads on while the second is counted)
        const double written = tile_requests(server.stats(true));
        EXPECT_LE(written, 0.03 * read) << "the write asked again for what was read: " << written << " of " << read;
        RecordProperty("first_open_tile_requests", std::to_string(read));
        RecordProperty("write_tile_requests", std::to_string(written));

        Opened second(paths, folder);
        ASSERT_TRUE(second.session.open());
        const auto asked = server.stats(true);
        EXPECT_EQ(tile_requests(asked), 0) << "the second open asked the tiles: " << asked.dump();
        EXPECT_EQ(second.from_sidecar(), 36u);
        EXPECT_EQ(second.session.scheduler->stats().chunk_points.done, chunk_points);
        EXPECT_FALSE(second.write()) << "nothing new to keep";
    }
    // Tile 7 moved on the server (its ETag changes, not its size): named when read in full, and read itself.
    auto m = nlohmann::json::parse(std::ifstream(manifest));
    m.at("tiles").at(7).at("shift").at(0) = m.at("tiles").at(7).at("shift").at(0).get<double>() + 100.0;
    std::ofstream(manifest) << m.dump(1);
    test::ReplicaServer::Options options;
    options.port = port;
    test::ReplicaServer moved(manifest, options);
    Opened third(paths, folder);
    ASSERT_TRUE(third.session.open());
    EXPECT_EQ(third.from_sidecar(), 36u);
    dataset::take_stale_tile_warnings();
    std::size_t stale = 0;
    for (const auto& t : third.session.dataset->tiles) {
        stale += dataset::stale_tile_check(t.tile, io::File::open(t.tile.path())) ? 1 : 0;
    }
    EXPECT_EQ(stale, 1u);
    const auto warnings = dataset::take_stale_tile_warnings().messages();
    ASSERT_EQ(warnings.size(), 1u);
    EXPECT_NE(warnings[0].find(m.at("tiles").at(7).at("file").get<std::string>()), std::string::npos) << warnings[0];
    fs::remove_all(dir);
}

// Tile URLs (no catalog: their sources have no item, and every header is read as the dataset opens).
TEST(OverviewCache, TileURLsOpenFromTheirSidecarTheSecondTime) {
    net::RangeCache::configure({{}, 0});
    const fs::path dir = fresh_dir("urls");
    const fs::path manifest = replica(dir);
    test::ReplicaServer server(manifest);
    std::vector<std::string> paths;
    const auto m = nlohmann::json::parse(std::ifstream(manifest));
    for (const auto& t : m.at("tiles")) paths.push_back(server.tile_url(t.at("file").get<std::string>()));
    ASSERT_EQ(paths.size(), 36u);
    const fs::path folder = dir / "cache";
    auto first = std::make_unique<Opened>(paths, folder);
    ASSERT_TRUE(first->session.open());
    const double read = tile_requests(server.stats(true));
    EXPECT_TRUE(first->write());
    const auto first_chunk_points = first->session.scheduler->stats().chunk_points.done;
    const auto first_file = first->cache->file();
    first.reset();  // (nothing of the first session reads on while the second is counted)
    EXPECT_LE(tile_requests(server.stats(true)), 0.03 * read);
    Opened second(paths, folder);
    ASSERT_TRUE(second.session.open());
    const auto asked = server.stats(true);
    EXPECT_EQ(tile_requests(asked), 0) << "the second open asked the tiles: " << asked.dump();
    EXPECT_EQ(second.from_sidecar(), paths.size());
    EXPECT_EQ(second.session.scheduler->stats().chunk_points.done, first_chunk_points);
    paths.pop_back();  // other URLs: another sidecar
    Opened fewer(paths, folder);
    ASSERT_TRUE(fewer.session.open());
    EXPECT_EQ(fewer.from_sidecar(), 0u);
    EXPECT_NE(fewer.cache->file(), first_file);
    fs::remove_all(dir);
}

TEST(OverviewCache, ADamagedSidecarIsNamedIgnoredAndWrittenAgain) {
    net::RangeCache::configure({{}, 0});
    const fs::path dir = fresh_dir("damaged");
    test::ReplicaServer server(replica(dir));
    const std::vector<std::string> paths = {server.catalog_url()};
    const fs::path folder = dir / "cache";
    const fs::path file = OverviewCache(paths, {folder, 1ull << 30}).file();
    fs::create_directories(folder);
    std::ofstream(file) << "not a sidecar";
    Opened first(paths, folder);
    ASSERT_TRUE(first.session.open());
    EXPECT_EQ(first.from_sidecar(), 0u);
    const auto messages = first.session.dataset->warnings.messages();
    const auto named = std::count_if(messages.begin(), messages.end(), [&](const std::string& w) {
        return w.find("overview sidecar not used") != w.npos && w.find(file.filename().string()) != w.npos;
    });
    EXPECT_EQ(named, 1) << testing::PrintToString(messages);
    EXPECT_TRUE(first.write());
    EXPECT_EQ(dataset::read_overview_sidecar(file.string()).entries.size(), 36u);
    Opened second(paths, folder);
    ASSERT_TRUE(second.session.open());
    EXPECT_EQ(second.from_sidecar(), 36u);
    fs::remove_all(dir);
}

TEST(OverviewCache, ABoundBelowTheSidecarKeepsNothingAndSaysSo) {
    net::RangeCache::configure({{}, 0});
    const fs::path dir = fresh_dir("bound");
    test::ReplicaServer server(replica(dir));
    const fs::path folder = dir / "cache";
    fs::create_directories(folder);
    std::ofstream(folder / "old.overview.laz") << std::string(3000, 'x');  // least recently used: dropped first
    Opened first({server.catalog_url()}, folder, 2000);
    ASSERT_TRUE(first.session.open());
    EXPECT_FALSE(first.write());
    EXPECT_FALSE(fs::exists(folder / "old.overview.laz"));
    EXPECT_FALSE(fs::exists(first.cache->file()));
    const auto note = first.cache->take_note();
    ASSERT_TRUE(note.has_value());
    EXPECT_NE(note->find("larger than --cache-size"), std::string::npos) << *note;
    fs::remove_all(dir);
}

TEST(OverviewCache, AnUnwritableFolderIsOneLineAndTheViewGoesOn) {
    net::RangeCache::configure({{}, 0});
    const fs::path dir = fresh_dir("unwritable");
    test::ReplicaServer server(replica(dir));
    std::ofstream(dir / "file") << "a file where the folder should be";
    Opened first({server.catalog_url()}, dir / "file" / "cache");
    EXPECT_TRUE(first.session.open());
    EXPECT_FALSE(first.write());
    const auto note = first.cache->take_note();
    ASSERT_TRUE(note.has_value());
    EXPECT_NE(note->find("overview cache: not kept"), std::string::npos) << *note;
    fs::remove_all(dir);
}

}  // namespace
}  // namespace lidarscout::viewer
