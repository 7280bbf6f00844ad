// The overview sidecar (dataset/overview_sidecar.hpp, overview_writer.hpp): its table round-trips and a
// malformed one is an Error; the Hilbert order visits a block's cells one step apart; a catalog opened
// through its sidecar has the tiles' own headers, chunk tables and chunk points (bit for bit), and `scan`
// says the same with and without it, locally and through the replica server, where the overview then
// costs no request to the tiles; a loader that releases the records leaves its grid every point; a tile
// changed since the sidecar was written is named and read itself; a sidecar of many chunks, decoded a few at a
// time, gives every record back.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <functional>
#include <numeric>
#include <set>
#include <string>

#include <nlohmann/json.hpp>

#include "core/error.hpp"
#include "core/patch_grid.hpp"
#include "core/thread_pool.hpp"
#include "dataset/catalog_writer.hpp"
#include "dataset/chunk_point_loader.hpp"
#include "dataset/chunk_points.hpp"
#include "dataset/dataset.hpp"
#include "dataset/overview_sidecar.hpp"
#include "dataset/overview_writer.hpp"
#include "dataset/stac_catalog.hpp"
#include "io/file.hpp"
#include "las/header_writer.hpp"
#include "net/remote_file.hpp"
#include "replica_server.hpp"
#include "test_data.hpp"

namespace lidarscout::dataset {
namespace {

namespace fs = std::filesystem;

fs::path survey() { return test::surveys_dir() / "ky-jmo335-eastern-kentucky"; }
std::vector<std::string> some_tiles() {
    return {(survey() / "N117E379.laz").string(), (survey() / "N117E381.laz").string(),
            (survey() / "N119E379.laz").string()};
}

std::string file_text(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

fs::path fresh_dir(const std::string& name) {
    const fs::path d = fs::temp_directory_path() / ("lidarscout_overview_" + name + "_" + std::to_string(::getpid()));
    fs::remove_all(d);
    fs::create_directories(d);
    return d;
}

nlohmann::json scan(const std::string& args) {
    std::string out;
    const std::string cmd = std::string(LIDARSCOUT_CLI) + " scan --json --cache-size 0 " + args + " 2>/dev/null";
    EXPECT_EQ(test::run_command(cmd, out), 0) << cmd;
    auto j = nlohmann::json::parse(out, nullptr, false);
    for (const char* key : {"chunk_points_per_second", "seconds_chunk_points", "seconds_headers", "requests",
                            "bytes", "retries", "requests_per_tile", "bytes_per_tile", "opens_in_one_request",
                            "open_fallbacks"}) {
        j.erase(key);  // (timings, and what the network cost: compared on their own)
    }
    return j;
}

// Writes `paths` as DIR/catalog.vpc with its sidecar (through the library); returns the sidecar's path.
std::string write_with_overview(const std::vector<std::string>& paths, const fs::path& dir) {
    const Dataset ds = open_dataset(paths);
    CatalogWriteOptions options;
    options.overview = overview_path_for((dir / "catalog.vpc").string());
    const auto written = write_overview(ds, catalog_ids(ds), options.overview);
    EXPECT_EQ(written.tiles, paths.size());
    EXPECT_EQ(written.held, paths.size());
    write_catalog(ds, (dir / "catalog.vpc").string(), options);
    return options.overview;
}

TEST(OverviewSidecar, TableRoundTripsAndAMalformedOneIsAnError) {
    OverviewEntry e;
    e.id = "N117E379";
    e.made_from = {1988620, "mtime 12345"};
    e.head.assign(600, 7);
    e.head[94] = 227, e.head[95] = 0, e.head[96] = 0x10, e.head[97] = 2, e.head[98] = 0, e.head[99] = 0;  // VLRs to 528
    e.tail = {1, 2, 3};
    e.first_point = 40, e.points = 38, e.delta = {1, -2, 3};
    OverviewEntry f = e;
    f.id = "N117E380";
    const OverviewEntry both[] = {e, f};
    const auto payload = serialize_overview_table(both);
    const auto back = parse_overview_table(payload, "t");
    ASSERT_EQ(back.size(), 2u);
    EXPECT_EQ(back[1].id, "N117E380");
    EXPECT_EQ(back[0].head, e.head);
    EXPECT_EQ(back[0].tail, e.tail);
    EXPECT_EQ(back[0].made_from, e.made_from);
    EXPECT_EQ(back[0].delta, e.delta);
    EXPECT_EQ(back[0].points, 38u);
    const std::span<const std::uint8_t> cut(payload.data(), payload.size() - 1);
    EXPECT_THROW(parse_overview_table(cut, "t"), Error);
    EXPECT_THROW(parse_overview_table(std::span(payload).subspan(1), "t"), Error);
}

// Made on a pool, in runs of entries, a table of thousands is the one made on one thread (each entry at its place,
// ids, heads, tails and points of different lengths); cut anywhere, it is an Error all the same.
TEST(OverviewSidecar, ATableMadeOnAPoolIsTheOneMadeOnOneThread) {
    std::vector<OverviewEntry> entries(3000);
    for (std::size_t k = 0; k < entries.size(); ++k) {
        OverviewEntry& e = entries[k];
        e.id = "tile-" + std::to_string(k * 7919);
        e.made_from = {1000 + k, k % 3 ? "\"etag-" + std::to_string(k) + "\"" : ""};
        e.head.assign(300 + k % 5, static_cast<std::uint8_t>(k));
        e.head[94] = 227, e.head[95] = 0, e.head[96] = 0, e.head[97] = 0;  // no VLR block
        e.tail.assign(k % 11, static_cast<std::uint8_t>(k + 1));
        e.first_point = 38 * k, e.points = static_cast<std::uint32_t>(k % 40);
        e.delta = {static_cast<std::int64_t>(k), -1, 2};
    }
    const auto payload = serialize_overview_table(entries);
    ThreadPool pool(2);
    const auto serial = parse_overview_table(payload, "t");
    const auto pooled = parse_overview_table(payload, "t", &pool);
    ASSERT_EQ(pooled.size(), entries.size());
    ASSERT_EQ(serial.size(), entries.size());
    for (std::size_t k = 0; k < entries.size(); ++k) {
        EXPECT_EQ(pooled[k].id, entries[k].id) << k;
        EXPECT_EQ(pooled[k].head, entries[k].head) << k;
        EXPECT_EQ(serial[k].head, entries[k].head) << k;
        EXPECT_EQ(pooled[k].tail, entries[k].tail) << k;
        EXPECT_EQ(pooled[k].made_from, entries[k].made_from) << k;
        EXPECT_EQ(pooled[k].first_point, entries[k].first_point) << k;
        EXPECT_EQ(pooled[k].points, entries[k].points) << k;
        EXPECT_EQ(pooled[k].delta, entries[k].delta) << k;
    }
    for (const std::size_t cut : {payload.size() - 1, payload.size() / 2, std::size_t{20}}) {
        EXPECT_THROW(parse_overview_table(std::span(payload).first(cut), "t", &pool), Error) << cut;
    }
    auto lying = payload;  // a count of 4 billion entries (after the signature, version and VLR blocks' count)
    std::fill(lying.begin() + 12, lying.begin() + 16, 0xff);
    EXPECT_THROW(parse_overview_table(lying, "t", &pool), Error) << "no room made for what is not there";
    EXPECT_THROW(parse_overview_table(lying, "t"), Error);
}

TEST(OverviewSidecar, HilbertOrderVisitsABlocksCellsOneStepApart) {
    std::vector<std::pair<std::uint64_t, std::pair<int, int>>> cells;
    for (int x = 0; x < 16; ++x) {
        for (int y = 0; y < 16; ++y) cells.push_back({hilbert_index(x, y), {x, y}});
    }
    std::sort(cells.begin(), cells.end());
    for (std::size_t k = 0; k < cells.size(); ++k) {
        ASSERT_EQ(cells[k].first, k);  // the first 256 steps cover the 16 x 16 block
        if (k == 0) continue;
        const auto [x0, y0] = cells[k - 1].second;
        const auto [x1, y1] = cells[k].second;
        EXPECT_EQ(std::abs(x1 - x0) + std::abs(y1 - y0), 1) << k;
    }
}

TEST(OverviewSidecar, ACatalogOpensFromItWithTheTilesOwnMetadataAndChunkPoints) {
    const fs::path dir = fresh_dir("local");
    write_with_overview(some_tiles(), dir);
    const Dataset placed = open_dataset({(dir / "catalog.vpc").string()});
    const Dataset read = open_dataset(some_tiles());
    ASSERT_EQ(placed.tiles.size(), read.tiles.size());
    EXPECT_TRUE(placed.skipped.empty());
    for (std::size_t i = 0; i < read.tiles.size(); ++i) {
        const Tile& p = placed.tiles[i].tile;
        const Tile& r = read.tiles[i].tile;
        ASSERT_TRUE(p.file->overview) << r.path();
        EXPECT_EQ(las::serialize_header(p.header), las::serialize_header(r.header));
        EXPECT_EQ(p.chunks()->chunks(), r.chunks()->chunks());
        EXPECT_EQ(p.vlrs(), r.vlrs());
        const auto records = overview_records(p, placed.tiles[i].chunk_points);
        ASSERT_EQ(records.size(), read.tiles[i].chunk_points * r.header.record_length);
        const io::File file = io::File::open(r.path());
        const auto locations = chunk_point_locations(r);
        for (std::size_t k = 0; k < locations.size(); ++k) {
            const auto own = file.read_vector(locations[k].offset, r.header.record_length);
            ASSERT_TRUE(std::equal(own.begin(), own.end(), records.begin() + k * own.size())) << r.path() << " " << k;
        }
    }
    const auto with = scan((dir / "catalog.vpc").string());
    EXPECT_GT(with.at("chunk_points").get<int>(), 0);
    EXPECT_EQ(with.dump(1), scan("--no-overview " + (dir / "catalog.vpc").string()).dump(1));
    fs::remove_all(dir);
}

// A sidecar of more LAZ chunks than are decoded at once (two per thread: the rest waits until the tiles before it
// are taken) gives every tile's records back, bit for bit.
TEST(OverviewSidecar, ASidecarOfManyChunksIsDecodedAPieceAtATimeAndGivesEveryRecordBack) {
    const fs::path dir = fresh_dir("many_chunks");
    const Dataset ds = open_dataset(some_tiles());
    const std::vector<std::string> ids = catalog_ids(ds);
    // each tile's chunk points repeated: together more than 2 x threads chunks of 50,000 points
    const std::size_t per_tile = (2 * ThreadPool::shared().size() * 50'000) / ds.tiles.size() + 30'000;
    std::vector<std::vector<std::uint8_t>> records(ds.tiles.size());
    for (std::size_t i = 0; i < ds.tiles.size(); ++i) {
        const Tile& t = ds.tiles[i].tile;
        const io::File file = io::File::open(t.path());
        std::vector<std::uint8_t> own;
        for (const auto& at : chunk_point_locations(t)) {
            const auto record = file.read_vector(at.offset, t.header.record_length);
            own.insert(own.end(), record.begin(), record.end());
        }
        ASSERT_FALSE(own.empty());
        while (records[i].size() < per_tile * t.header.record_length) {
            records[i].insert(records[i].end(), own.begin(), own.end());
        }
    }
    const auto expected = records;
    const std::string path = (dir / "catalog.overview.laz").string();
    const auto written = write_overview(ds, ids, records, path);
    ASSERT_EQ(written.held, ds.tiles.size());
    const OverviewSidecar s = read_overview_sidecar(path);
    ASSERT_EQ(s.entries.size(), ds.tiles.size());
    std::set<std::string> seen;
    for (std::size_t k = 0; k < s.entries.size(); ++k) {
        const auto& e = s.entries[k];
        const std::size_t i = static_cast<std::size_t>(std::find(ids.begin(), ids.end(), e.id) - ids.begin());
        ASSERT_LT(i, ids.size()) << e.id;
        seen.insert(e.id);
        const auto& block = *s.blocks.at(s.block_of.at(k));
        const std::size_t bytes = std::size_t{e.points} * s.record_length;
        ASSERT_EQ(bytes, expected[i].size()) << e.id;
        ASSERT_LE(s.record_starts.at(k) + bytes, block.size()) << e.id;
        EXPECT_TRUE(std::equal(expected[i].begin(), expected[i].end(), block.begin() + s.record_starts[k])) << e.id;
    }
    EXPECT_EQ(seen.size(), ds.tiles.size());
    fs::remove_all(dir);
}

// The viewer's loader lets the sidecar's records go once its grid holds them: the grid has every chunk point,
// the records are gone, and a loader that keeps them (the default: `scan`, `dem`) leaves them.
TEST(OverviewSidecar, ALoaderThatReleasesLeavesTheGridItsPointsAndTheRecordsGone) {
    const fs::path dir = fresh_dir("release");
    write_with_overview(some_tiles(), dir);
    for (const bool release : {false, true}) {
        const Dataset placed = open_dataset({(dir / "catalog.vpc").string()});
        const auto [ox, oy] = patch_grid_origin(placed);
        PatchGrid grid(ox, oy);
        ChunkPointLoaderOptions options;
        options.release_overview = release;
        ChunkPointLoader loader(placed, grid, options);
        loader.start();
        loader.wait();
        EXPECT_TRUE(loader.errors().empty());
        EXPECT_EQ(grid.size(), placed.chunk_point_count);
        for (const auto& t : placed.tiles) {
            ASSERT_TRUE(t.tile.file->overview);
            EXPECT_EQ(overview_records(t.tile, t.chunk_points).empty(), release) << t.tile.path();
            EXPECT_EQ(t.tile.file->overview->records->empty(), release);
        }
    }
    // A block goes once each of its tiles' records to take was taken (the three share one block).
    const Dataset placed = open_dataset({(dir / "catalog.vpc").string()});
    const std::uint32_t taking[] = {0, 2};
    OverviewRelease releasing(placed.tiles, taking);
    const auto held = [&](std::size_t i) {
        return !overview_records(placed.tiles[i].tile, placed.tiles[i].chunk_points).empty();
    };
    ASSERT_TRUE(held(0) && held(1) && held(2));
    releasing.taken(placed.tiles[2].tile);
    EXPECT_TRUE(held(0) && held(1) && held(2));
    releasing.taken(placed.tiles[0].tile);
    EXPECT_FALSE(held(0) || held(1) || held(2));
    fs::remove_all(dir);
}

TEST(OverviewSidecar, ItsTilesGoIntoTheGridInBatchesTheNearestAlone) {
    const fs::path dir = fresh_dir("batches");
    std::vector<std::string> every;
    for (const auto& e : fs::directory_iterator(survey())) {
        if (e.path().extension() == ".laz") every.push_back(e.path().string());
    }
    std::sort(every.begin(), every.end());
    ASSERT_GE(every.size(), 9u) << "enough tiles for batches of several";
    write_with_overview(every, dir);
    const Dataset placed = open_dataset({(dir / "catalog.vpc").string()});
    const auto [ox, oy] = patch_grid_origin(placed);
    PatchGrid grid(ox, oy);
    ChunkPointLoader loader(placed, grid);
    std::vector<std::vector<std::uint32_t>> batches;
    std::set<CellKey> told;
    loader.on_tile_done([&](std::span<const std::uint32_t> tiles, std::span<const CellKey> cells) {
        batches.emplace_back(tiles.begin(), tiles.end());
        EXPECT_TRUE(std::adjacent_find(cells.begin(), cells.end(), std::greater_equal<>()) == cells.end())
            << "a batch's cells sorted, each once";
        told.insert(cells.begin(), cells.end());
    });
    const auto& focus = placed.tiles[3].bounds_m;
    loader.set_focus(focus.centre_x(), focus.centre_y());
    loader.start();
    loader.wait();
    EXPECT_TRUE(loader.errors().empty());
    EXPECT_EQ(grid.size(), placed.chunk_point_count);
    ASSERT_GE(batches.size(), 2u);
    EXPECT_EQ(batches[0], std::vector<std::uint32_t>{3}) << "the tile at the focus first, alone";
    EXPECT_TRUE(std::any_of(batches.begin(), batches.end(), [](const auto& b) { return b.size() > 1; }));
    std::vector<std::uint32_t> tiles;
    for (const auto& b : batches) tiles.insert(tiles.end(), b.begin(), b.end());
    std::sort(tiles.begin(), tiles.end());
    std::vector<std::uint32_t> each(placed.tiles.size());
    std::iota(each.begin(), each.end(), 0u);
    EXPECT_EQ(tiles, each) << "every tile told once";
    const auto cells = grid.cells();
    EXPECT_EQ(told, std::set<CellKey>(cells.begin(), cells.end())) << "the cells told are those the points fell in";
    EXPECT_EQ(loader.tiles_done(), placed.tiles.size());
    fs::remove_all(dir);
}

// The catalog names its sidecar before its items, and read_catalog tells it as soon as it is read; a prefetch
// of it is what read_overview_sidecar then gives, once; one not taken is forgotten; a prefetch's error is thrown
// by the read that takes it.
TEST(OverviewSidecar, ACatalogNamesItsSidecarFirstAndItsPrefetchIsTakenOnce) {
    const fs::path dir = fresh_dir("prefetch");
    const std::string sidecar = write_with_overview(some_tiles(), dir);
    const std::string vpc = (dir / "catalog.vpc").string();
    const std::string text = file_text(vpc);
    EXPECT_LT(text.find("\"links\""), text.find("\"features\"")) << "the sidecar's link before the items";
    std::vector<std::string> told;
    const Catalog c = read_catalog(vpc, {}, {}, [&](const std::string& p) { told.push_back(p); });
    ASSERT_EQ(told, std::vector<std::string>{c.overview});
    EXPECT_EQ(fs::canonical(told[0]), fs::canonical(sidecar));

    const OverviewSidecar direct = read_overview_sidecar(sidecar);
    EXPECT_FALSE(direct.decoding) << "read without a prefetch: decoded before it is given";
    prefetch_overview_sidecar(sidecar);
    const OverviewSidecar taken = read_overview_sidecar(sidecar);
    ASSERT_TRUE(taken.decoding) << "a prefetch's points are decoded while its taker goes on";
    EXPECT_TRUE(taken.decoding->wait());
    ASSERT_EQ(taken.entries.size(), direct.entries.size());
    ASSERT_EQ(taken.blocks.size(), direct.blocks.size());
    for (std::size_t b = 0; b < direct.blocks.size(); ++b) EXPECT_EQ(*taken.blocks[b], *direct.blocks[b]);
    EXPECT_EQ(taken.record_starts, direct.record_starts);
    // Downloaded at once, decoded once its catalog is read (or when taken, as above): the same sidecar.
    prefetch_overview_sidecar(sidecar);
    decode_overview_prefetch();
    const OverviewSidecar decoded = read_overview_sidecar(sidecar);
    ASSERT_TRUE(decoded.decoding);
    EXPECT_TRUE(decoded.decoding->wait());
    ASSERT_EQ(decoded.blocks.size(), direct.blocks.size());
    for (std::size_t b = 0; b < direct.blocks.size(); ++b) EXPECT_EQ(*decoded.blocks[b], *direct.blocks[b]);

    prefetch_overview_sidecar(sidecar);
    fs::remove(sidecar);  // the prefetch has it (or fails); a read after forgetting it asks the file again
    forget_overview_prefetch();
    EXPECT_THROW(read_overview_sidecar(sidecar), Error);
    prefetch_overview_sidecar(sidecar);  // of a file that is gone: its error comes with the read that takes it
    try {
        read_overview_sidecar(sidecar);
        ADD_FAILURE() << "a missing sidecar read";
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find("catalog.overview.laz"), std::string::npos) << e.what();
    }
    fs::remove_all(dir);
}

TEST(OverviewSidecar, AnUnreadableSidecarIsOneWarningAndTheTilesAreRead) {
    const fs::path dir = fresh_dir("broken");
    const std::string sidecar = write_with_overview(some_tiles(), dir);
    fs::resize_file(sidecar, 1000);
    const Dataset ds = open_dataset({(dir / "catalog.vpc").string()});
    EXPECT_EQ(ds.tiles.size(), some_tiles().size());
    const auto messages = ds.warnings.messages();
    EXPECT_EQ(std::count_if(messages.begin(), messages.end(),
                            [](const std::string& m) { return m.find("overview sidecar not used") != m.npos; }),
              1);
    for (const auto& t : ds.tiles) EXPECT_FALSE(t.tile.file->overview);
    // Opened placed (as the viewer opens): the items place the tiles, the sidecar's warning kept, no header read.
    DatasetOptions placed;
    placed.placed = true;
    const Dataset by_items = open_dataset({(dir / "catalog.vpc").string()}, placed);
    EXPECT_TRUE(by_items.placed);
    EXPECT_EQ(by_items.tiles.size(), some_tiles().size());
    EXPECT_EQ(by_items.tiles_ready(), 0u);
    const auto placed_messages = by_items.warnings.messages();
    EXPECT_EQ(std::count_if(placed_messages.begin(), placed_messages.end(),
                            [](const std::string& m) { return m.find("overview sidecar not used") != m.npos; }),
              1);
    fs::remove_all(dir);
}

// A sidecar whose table reads but whose points do not decode (its first LAZ chunk's first bytes overwritten): the
// catalog opens from its table, the points' decoding (going on after the open) fails with one warning naming the
// sidecar, and every tile's chunk points come from the tile itself, also through the viewer's loader.
TEST(OverviewSidecar, PointsThatDoNotDecodeAreOneWarningAndTheTilesGiveTheirOwn) {
    const fs::path dir = fresh_dir("bad_points");
    const std::string sidecar = write_with_overview(some_tiles(), dir);
    {
        const io::File file = io::File::open(sidecar);
        const Tile t = read_tile(file);
        std::fstream f(sidecar, std::ios::in | std::ios::out | std::ios::binary);
        f.seekp(static_cast<std::streamoff>(t.header.offset_to_point_data + 8));  // (past the chunk table's pointer)
        const std::string junk(64, '\xA5');
        f.write(junk.data(), static_cast<std::streamsize>(junk.size()));
    }
    take_stale_tile_warnings();
    const Dataset read = open_dataset(some_tiles());
    for (int round = 0; round < 2; ++round) {
        const Dataset placed = open_dataset({(dir / "catalog.vpc").string()});
        ASSERT_EQ(placed.tiles.size(), read.tiles.size());
        for (std::size_t i = 0; i < placed.tiles.size(); ++i) {
            const Tile& t = placed.tiles[i].tile;
            ASSERT_TRUE(t.file->overview) << "placed from the sidecar's table";
            EXPECT_TRUE(overview_records(t, placed.tiles[i].chunk_points).empty());
            const auto own = tile_chunk_points(read.tiles[i].tile);
            const auto got = tile_chunk_points(t);
            ASSERT_EQ(got.size(), own.size());
            for (std::size_t k = 0; k < own.size(); ++k) {
                EXPECT_EQ(got[k].index, own[k].index);
                EXPECT_EQ(got[k].point.x, own[k].point.x);
                EXPECT_EQ(got[k].point.z, own[k].point.z);
            }
        }
        const auto [ox, oy] = patch_grid_origin(placed);
        PatchGrid grid(ox, oy);
        ChunkPointLoaderOptions options;
        options.release_overview = round == 1;
        ChunkPointLoader loader(placed, grid, options);
        loader.start();
        loader.wait();
        EXPECT_TRUE(loader.errors().empty());
        EXPECT_EQ(grid.size(), placed.chunk_point_count);
        const auto messages = take_stale_tile_warnings().messages();
        ASSERT_EQ(messages.size(), 1u) << testing::PrintToString(messages);
        EXPECT_NE(messages[0].find("catalog.overview.laz"), std::string::npos) << messages[0];
        EXPECT_NE(messages[0].find("points not used"), std::string::npos) << messages[0];
    }
    fs::remove_all(dir);
}

TEST(OverviewSidecar, ATileChangedSinceIsNamedAndReadItself) {
    const fs::path dir = fresh_dir("stale");
    const auto tiles = some_tiles();
    std::vector<std::string> copies;
    for (const auto& t : tiles) {
        copies.push_back((dir / fs::path(t).filename()).string());
        fs::copy_file(t, copies.back());
    }
    write_with_overview(copies, dir);
    fs::remove(copies[1]);
    fs::copy_file(tiles[0], copies[1]);  // another tile, of another size, under its name
    const Dataset ds = open_dataset({(dir / "catalog.vpc").string()});
    ASSERT_EQ(ds.tiles.size(), 3u);
    take_stale_tile_warnings();
    for (int twice = 0; twice < 2; ++twice) {
        for (const auto& t : ds.tiles) {
            const auto fresh = stale_tile_check(t.tile, io::File::open(t.tile.path()));
            EXPECT_EQ(fresh.has_value(), t.tile.path() == copies[1]) << t.tile.path();
            if (!fresh) continue;
            const Tile own = read_tile(io::File::open(tiles[0]));
            EXPECT_EQ(las::serialize_header(fresh->header), las::serialize_header(own.header));
        }
    }
    const Diagnostics warnings = take_stale_tile_warnings();
    ASSERT_EQ(warnings.messages().size(), 1u);  // named once
    EXPECT_NE(warnings.messages()[0].find(copies[1]), std::string::npos) << warnings.messages()[0];
    fs::remove_all(dir);
}

// A 20 x 20 virtual replica of a ky-jmo335 tile: its sidecar written from the manifest, served with the
// replica's catalog; `scan` of the catalog equals `scan` of the manifest and asks the tiles for nothing.
TEST(OverviewSidecar, ThroughTheReplicaServerTheOverviewAsksTheTilesForNothing) {
    const fs::path dir = fresh_dir("replica");
    const std::string cli = LIDARSCOUT_CLI;
    const std::string replicate = cli + " synth replicate " + some_tiles()[0] + " --grid 20x20 --virtual -o " +
                                  (dir / "r").string() + " >/dev/null";
    ASSERT_EQ(std::system(replicate.c_str()), 0);
    const fs::path manifest = dir / "r" / "replicate.json";
    const std::string catalog = cli + " catalog " + manifest.string() + " -o " + (dir / "r" / "catalog.vpc").string() +
                                " --overview >/dev/null";
    ASSERT_EQ(std::system(catalog.c_str()), 0);
    test::ReplicaServer::Options options;
    options.overview = (dir / "r" / "catalog.overview.laz").string();
    test::ReplicaServer server(manifest, options);
    const auto local = scan(manifest.string());
    server.stats(true);
    const auto remote = scan(server.catalog_url());
    EXPECT_EQ(remote.dump(1), local.dump(1));
    const auto stats = server.stats(true);
    const auto requests = [&](const char* kind) { return stats.at("kinds").at(kind).at("requests").get<double>(); };
    EXPECT_LE(requests("tile") + requests("tile_head"), 0.01 * 400) << stats.dump(1);
    EXPECT_LE(requests("overview"), 3) << stats.dump(1);
    EXPECT_GE(requests("overview"), 1) << stats.dump(1);
    const auto without = scan("--no-overview " + server.catalog_url());
    EXPECT_EQ(without.dump(1), local.dump(1));
    EXPECT_GE(server.stats().at("tiles_touched").get<int>(), 400);
    // Its sidecar not used, the catalog's items place its tiles as any catalog's do: open at once, no tile asked
    // (it had read every header first: a country's 152,100 in 61 s, 1.4 GB under a 1 GiB budget).
    net::RemoteFile::forget_all();
    server.stats(true);
    DatasetOptions placed;
    placed.placed = true;
    placed.use_overview = false;
    const Dataset ds = open_dataset({server.catalog_url()}, placed);
    EXPECT_TRUE(ds.placed);
    EXPECT_EQ(ds.tiles.size(), 400u);
    EXPECT_EQ(server.stats().at("tiles_touched").get<int>(), 0);
    fs::remove_all(dir);
}

}  // namespace
}  // namespace lidarscout::dataset
