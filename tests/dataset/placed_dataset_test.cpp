// A dataset placed by its catalog (dataset/dataset.hpp, DatasetOptions::placed), through the replica server
// (a 12 x 12 virtual replica of a ky-jmo335 tile): it opens from the items with no request to a tile;
// ensure_tiles reads the headers asked for and no other; once every header is read it equals the dataset
// opened by reading them (tiles, headers, bounds, counts), and so do the chunk points the loader reads
// (headers on demand); a header that disagrees with its item is corrected and named (as it is read, for a
// dataset shared); a tile that cannot
// be read is skipped with its line, the rest kept; `clip` and `dem` of a small region ask only its tiles and
// write what the eager path writes; a search's pages reach the caller as they are read.
#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <functional>
#include <iterator>
#include <fstream>
#include <span>
#include <string>
#include <vector>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "core/patch_grid.hpp"
#include "dataset/chunk_point_loader.hpp"
#include "dataset/dataset.hpp"
#include "dataset/stac_catalog.hpp"
#include "las/header_writer.hpp"
#include "core/thread_pool.hpp"
#include "pipelines/region_points.hpp"
#include "net/range_cache.hpp"
#include "net/remote_file.hpp"
#include "replica_server.hpp"
#include "test_data.hpp"

namespace lidarscout::dataset {
namespace {

namespace fs = std::filesystem;

constexpr std::size_t kTiles = 144;

// One replica (made once per process) and its server; the disk range cache off (every read a request).
struct Replica {
    fs::path dir;
    std::unique_ptr<test::ReplicaServer> server;
    ~Replica() {
        server.reset();
        if (!dir.empty()) fs::remove_all(dir);
    }
};

Replica& replica() {
    static Replica r;
    if (r.server) return r;
    net::RangeCache::configure({{}, 0});
    r.dir = fs::temp_directory_path() / ("lidarscout_placed_" + std::to_string(::getpid()));
    fs::remove_all(r.dir);
    const std::string tile = (test::surveys_dir() / "ky-jmo335-eastern-kentucky" / "N117E380.laz").string();
    const std::string cmd = std::string(LIDARSCOUT_CLI) + " synth replicate " + tile + " --grid 12x12 --virtual -o " +
                            (r.dir / "r").string() + " >/dev/null";
    if (std::system(cmd.c_str()) != 0) throw std::runtime_error("cannot make the replica: " + cmd);
    r.server = std::make_unique<test::ReplicaServer>(r.dir / "r" / "replicate.json");
    return r;
}

double tile_requests(bool reset = true) {
    const auto stats = replica().server->stats(reset);
    return stats.at("kinds").at("tile").at("requests").get<double>() +
           stats.at("kinds").at("tile_head").at("requests").get<double>();
}

Dataset open(const std::string& path, bool placed) {
    net::RemoteFile::forget_all();  // (remote files are kept by URL for the process: this open asks again)
    DatasetOptions options;
    options.placed = placed;
    return open_dataset({path}, options);
}

// The server's catalog with absolute hrefs, written to DIR/NAME after `edit` changed its items.
std::string local_catalog(const std::string& name, const std::function<void(nlohmann::json&)>& edit) {
    auto& r = replica();
    auto catalog = nlohmann::json::parse(r.server->fetch("catalog.vpc").body);
    for (auto& f : catalog.at("features")) {
        auto& href = f.at("assets").at("data").at("href");
        href = r.server->url(href.get<std::string>().substr(2));  // "./tiles/..." -> its URL
    }
    edit(catalog.at("features"));
    const fs::path path = r.dir / name;
    std::ofstream(path) << catalog.dump();
    return path.string();
}

TEST(PlacedDataset, OpensFromItsItemsWithoutATileRequest) {
    const std::string url = replica().server->catalog_url();
    tile_requests();
    const Dataset ds = open(url, true);
    EXPECT_EQ(tile_requests(), 0);
    ASSERT_TRUE(ds.placed);
    ASSERT_EQ(ds.tiles.size(), kTiles);
    EXPECT_EQ(ds.tiles_ready(), 0u);
    EXPECT_FALSE(ds.is_ready(0));
    const Dataset eager = open(url, false);
    EXPECT_FALSE(eager.placed);
    EXPECT_EQ(ds.point_count, eager.point_count);
    EXPECT_NEAR(ds.bounds_m.min_x, eager.bounds_m.min_x, 0.01);
    EXPECT_NEAR(ds.bounds_m.max_y, eager.bounds_m.max_y, 0.01);
    EXPECT_EQ(ds.path(5), eager.tiles[5].tile.path());
}

TEST(PlacedDataset, EnsureReadsTheTilesAskedForAloneThenEqualsTheEagerDataset) {
    const std::string url = replica().server->catalog_url();
    Dataset ds = open(url, true);
    replica().server->stats(true);
    net::RemoteFile::forget_all();
    const std::vector<std::uint32_t> some = {7, 3, 100};
    ensure_tiles(ds, some);
    EXPECT_EQ(replica().server->stats(true).at("tiles_touched").get<int>(), 3);
    for (const auto i : some) EXPECT_TRUE(ds.is_ready(i));
    EXPECT_EQ(ds.tiles_ready(), 3u);
    EXPECT_FALSE(ds.is_ready(0));
    ensure_all_tiles(ds);
    settle_tiles(ds);
    EXPECT_FALSE(ds.placed);  // every tile read: released
    const Dataset eager = open(url, false);
    ASSERT_EQ(ds.tiles.size(), eager.tiles.size());
    EXPECT_EQ(ds.point_count, eager.point_count);
    EXPECT_EQ(ds.chunk_point_count, eager.chunk_point_count);
    EXPECT_EQ(ds.warnings.messages(), eager.warnings.messages());
    EXPECT_TRUE(ds.skipped.empty());
    EXPECT_EQ(ds.frame.crs, eager.frame.crs);
    EXPECT_EQ(ds.frame.xy_to_metres, eager.frame.xy_to_metres);
    EXPECT_EQ(ds.frame.z_to_metres, eager.frame.z_to_metres);
    EXPECT_EQ(ds.bounds_m.min_x, eager.bounds_m.min_x);
    EXPECT_EQ(ds.bounds_m.max_z, eager.bounds_m.max_z);
    for (std::size_t i = 0; i < ds.tiles.size(); ++i) {
        const auto &a = ds.tiles[i], &b = eager.tiles[i];
        ASSERT_EQ(a.tile.path(), b.tile.path());
        EXPECT_EQ(las::serialize_header(a.tile.header), las::serialize_header(b.tile.header));
        EXPECT_EQ(a.tile.chunks()->size(), b.tile.chunks()->size());
        EXPECT_EQ(a.bounds_m.min_x, b.bounds_m.min_x);
        EXPECT_EQ(a.bounds_m.max_z, b.bounds_m.max_z);
        EXPECT_EQ(a.points, b.points);
        EXPECT_EQ(a.chunk_points, b.chunk_points);
        EXPECT_EQ(a.xy_to_metres, b.xy_to_metres);
    }
}

TEST(PlacedDataset, TheLoaderReadsHeadersOnDemandAndLoadsWhatTheEagerOneDoes) {
    const std::string url = replica().server->catalog_url();
    std::uint64_t loaded[2] = {0, 0}, total[2] = {0, 0};
    std::size_t cells[2] = {0, 0};
    for (const bool placed : {true, false}) {
        const Dataset ds = open(url, placed);
        const auto [ox, oy] = patch_grid_origin(ds);
        PatchGrid grid(ox, oy);
        ChunkPointLoader loader(ds, grid);
        loader.set_focus(ds.bounds_m.centre_x(), ds.bounds_m.centre_y());
        loader.start();
        loader.wait();
        EXPECT_TRUE(loader.errors().empty());
        EXPECT_EQ(loader.failed(), 0u);
        EXPECT_EQ(ds.tiles_ready(), kTiles);
        loaded[placed] = loader.loaded(), total[placed] = loader.total(), cells[placed] = grid.cells().size();
    }
    EXPECT_GT(loaded[0], 0u);
    EXPECT_EQ(loaded[1], loaded[0]);
    EXPECT_EQ(total[1], total[0]);  // the estimate made exact as headers came
    EXPECT_EQ(cells[1], cells[0]);
}

TEST(PlacedDataset, AHeaderThatDisagreesIsCorrectedAndNamed) {
    std::uint64_t real = 0;
    std::string id;
    const std::string vpc = local_catalog("disagrees.vpc", [&](nlohmann::json& items) {
        auto& p = items[10].at("properties");
        real = p.at("pc:count").get<std::uint64_t>();
        p["pc:count"] = real + 1000;
        id = items[10].at("id").get<std::string>();
    });
    Dataset ds = open(vpc, true);
    ASSERT_TRUE(ds.placed);
    EXPECT_EQ(ds.tiles[10].points, real + 1000);  // the item's, until its header is read
    ensure_tiles(ds, std::vector<std::uint32_t>{10});
    settle_tiles(ds);
    EXPECT_EQ(ds.tiles[10].points, real);
    ASSERT_EQ(ds.warnings.size(), 1u);
    const std::string line = ds.warnings.messages()[0];
    EXPECT_NE(line.find(id), std::string::npos) << line;
    EXPECT_NE(line.find("pc:count"), std::string::npos) << line;
    EXPECT_EQ(ds.point_count, open(replica().server->catalog_url(), false).point_count);
}

// While the dataset is shared (a viewer's), a tile whose header disagrees with its item is corrected where
// other threads look once its header is read (Dataset::bounds: the header's bounds, its item's until then;
// the placed fields stay) and named at once (Dataset::corrections: the line settle_tiles then puts in the
// warnings, and no other).
TEST(PlacedDataset, AHeaderThatDisagreesIsCorrectedForASharedDatasetAsItIsRead) {
    std::string id;
    const std::string vpc = local_catalog("moved.vpc", [&](nlohmann::json& items) {
        auto& box = items[10].at("properties").at("proj:bbox");
        for (const int k : {0, 3}) box[k] = box[k].get<double>() + 500.0;  // x moved by half a tile
        id = items[10].at("id").get<std::string>();
    });
    const Dataset eager = open(replica().server->catalog_url(), false);
    Dataset ds = open(vpc, true);
    ASSERT_TRUE(ds.placed);
    const Bounds item = ds.tiles[10].bounds_m;
    EXPECT_GT(item.min_x, eager.tiles[10].bounds_m.min_x + 100.0);  // (500 of the CRS's units: feet or metres)
    EXPECT_EQ(ds.bounds(10).min_x, item.min_x);
    EXPECT_EQ(ds.corrections_count(), 0u);
    ensure_tiles(ds, std::vector<std::uint32_t>{10, 11});
    EXPECT_DOUBLE_EQ(ds.bounds(10).min_x, eager.tiles[10].bounds_m.min_x);
    EXPECT_DOUBLE_EQ(ds.bounds(10).max_y, eager.tiles[10].bounds_m.max_y);
    EXPECT_DOUBLE_EQ(ds.bounds(11).min_x, eager.tiles[11].bounds_m.min_x);
    EXPECT_EQ(ds.tiles[10].bounds_m.min_x, item.min_x) << "a placed field written while the dataset is shared";
    ASSERT_EQ(ds.corrections_count(), 1u);
    const Diagnostics corrections = ds.corrections();
    ASSERT_EQ(corrections.size(), 1u);
    const std::string line = corrections[0].message;
    EXPECT_NE(line.find(id), std::string::npos) << line;
    EXPECT_NE(line.find("proj:bbox"), std::string::npos) << line;
    EXPECT_TRUE(ds.corrections(1).empty());
    settle_tiles(ds);
    ASSERT_EQ(ds.warnings.size(), 1u);
    EXPECT_EQ(ds.warnings.messages()[0], line);
    EXPECT_EQ(ds.corrections_count(), 0u);
    EXPECT_DOUBLE_EQ(ds.tiles[10].bounds_m.min_x, eager.tiles[10].bounds_m.min_x);
    EXPECT_DOUBLE_EQ(ds.bounds(10).min_x, eager.tiles[10].bounds_m.min_x);
}

// A STAC API search's pages reach the caller of find_tile_sources as they are read: each page handed over
// before the next is asked (when the k-th page arrives, the server has answered k times the requests of the
// first, none for the pages after), with whether more is to come, and the pages together are the sources.
TEST(PlacedDataset, ASearchsPagesArriveBeforeTheNextIsAsked) {
    auto& server = *replica().server;
    net::RemoteFile::forget_all();
    server.stats(true);
    struct Page {
        std::size_t items;
        bool more;
        int searches;  // search requests the server had answered then
    };
    std::vector<Page> pages;
    std::vector<std::string> paths;
    const auto arriving = [&](std::span<const TileSource> page, bool more) {
        const int searches = server.stats().at("kinds").at("search").at("requests").get<int>();
        pages.push_back({page.size(), more, searches});
        for (const auto& s : page) paths.push_back(s.path);
        if (!page.empty()) EXPECT_TRUE(page.front().item && page.front().item->count);
    };
    const FoundSources found = find_tile_sources({server.url("search?limit=50")}, arriving);
    ASSERT_EQ(pages.size(), 3u);
    for (std::size_t k = 0; k < pages.size(); ++k) {
        EXPECT_EQ(pages[k].items, k < 2 ? 50u : 0u);  // (the last page's come with what find_tile_sources returns)
        EXPECT_EQ(pages[k].more, k < 2);
        EXPECT_EQ(pages[k].searches, static_cast<int>(k + 1) * pages[0].searches);
    }
    EXPECT_EQ(server.stats().at("kinds").at("search").at("requests").get<int>(), 3 * pages[0].searches);
    EXPECT_LE(pages[0].searches, 3) << "a page of 50 items (80 KB) read in more round trips than its open and one";
    ASSERT_EQ(found.sources.size(), kTiles);
    ASSERT_EQ(paths.size(), 100u);
    for (std::size_t i = 0; i < paths.size(); ++i) EXPECT_EQ(paths[i], found.sources[i].path);
    DatasetOptions placed;
    placed.placed = true;
    EXPECT_TRUE(opens_placed(std::span(found.sources).first(50), placed));
}

TEST(PlacedDataset, ATileThatCannotBeReadIsSkippedWithItsLineTheRestKept) {
    const std::string vpc = local_catalog("missing.vpc", [&](nlohmann::json& items) {
        items[4].at("assets").at("data")["href"] = replica().server->url("tiles/no_such_tile.laz");
    });
    Dataset ds = open(vpc, true);
    ASSERT_TRUE(ds.placed);
    EXPECT_FALSE(ds.ready(4));
    EXPECT_NE(ds.ready_error(4).find("no_such_tile.laz"), std::string::npos) << ds.ready_error(4);
    EXPECT_TRUE(ds.ready(5));
    ensure_all_tiles(ds);
    settle_tiles(ds);
    EXPECT_EQ(ds.tiles.size(), kTiles - 1);
    ASSERT_EQ(ds.skipped.size(), 1u);
    EXPECT_NE(ds.skipped[0].error.find("no_such_tile.laz"), std::string::npos) << ds.skipped[0].error;
    EXPECT_NE(ds.skipped[0].error.find("item '"), std::string::npos) << ds.skipped[0].error;
}

// A pipeline's region read of a placed dataset, as the viewer's area and profile tools make it: the tiles
// the region touches have their headers read first, the others not, and the points are the eager path's.
TEST(PlacedDataset, ARegionReadOfAPlacedDatasetReadsItsTilesHeadersFirst) {
    const std::string url = replica().server->catalog_url();
    std::uint64_t kept[2] = {0, 0};
    for (const bool placed : {true, false}) {
        const Dataset ds = open(url, placed);
        const auto& b = ds.tiles[20].bounds_m;
        const double f = ds.frame.xy_to_metres, cx = b.centre_x() / f, cy = b.centre_y() / f;
        const pipelines::Region region = pipelines::box_region(cx - 100, cy - 100, cx + 100, cy + 100);
        const auto tiles = pipelines::tiles_touching(ds, region);
        ASSERT_EQ(tiles, std::vector<std::uint32_t>{20});
        EXPECT_EQ(ds.tiles_ready(), placed ? 1u : kTiles);
        ThreadPool pool(2);
        kept[placed] =
            pipelines::read_region_points(ds, tiles, region, PointFilter(), pool, [](const pipelines::RegionBatch&) {})
                .points_kept;
    }
    EXPECT_GT(kept[0], 0u);
    EXPECT_EQ(kept[1], kept[0]);
}

std::string file_bytes(const fs::path& path) {
    std::ifstream in(path, std::ios::binary);
    return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

// `clip` and `dem` of a box inside one tile: from the served catalog they ask that tile alone (and the few
// a DEM's blocks reach), and write what they write from the replica's manifest, byte for byte.
TEST(PlacedDataset, AClipOrDemOfASmallRegionAsksItsOwnTilesAlone) {
    auto& r = replica();
    const Dataset eager = open(r.server->catalog_url(), false);
    const auto& b = eager.tiles[20].bounds_m;  // a box inside one tile, in the CRS's units
    const double f = eager.frame.xy_to_metres, cx = b.centre_x() / f, cy = b.centre_y() / f;
    const std::string box = fmt::format("{},{},{},{}", cx - 100, cy - 100, cx + 100, cy + 100);
    const auto run = [&](const std::string& command, const std::string& input, const std::string& out) {
        std::string text;
        const std::string cmd = std::string(LIDARSCOUT_CLI) + " " + command + " --cache-size 0 " + input +
                                " --bounds " + box + " -o " + (r.dir / out).string() + " >/dev/null 2>&1";
        EXPECT_EQ(test::run_command(cmd, text), 0) << cmd;
    };
    const std::string manifest = (r.dir / "r" / "replicate.json").string();
    r.server->stats(true);
    run("clip", r.server->catalog_url(), "placed.laz");
    EXPECT_EQ(r.server->stats(true).at("tiles_touched").get<int>(), 1);
    run("clip", manifest, "local.laz");
    EXPECT_GT(fs::file_size(r.dir / "placed.laz"), 1000u);
    EXPECT_EQ(file_bytes(r.dir / "placed.laz"), file_bytes(r.dir / "local.laz"));
    run("dem", r.server->catalog_url(), "placed.tif");
    EXPECT_LE(r.server->stats(true).at("tiles_touched").get<int>(), 9);
    run("dem", manifest, "local.tif");
    EXPECT_GT(fs::file_size(r.dir / "placed.tif"), 1000u);
    EXPECT_EQ(file_bytes(r.dir / "placed.tif"), file_bytes(r.dir / "local.tif"));
}

}  // namespace
}  // namespace lidarscout::dataset
