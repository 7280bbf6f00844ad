// Full-resolution residency on a real survey: every tile in view ends at full resolution when
// the budget allows; a tile that must make room drops to its coarse levels (a prefix of its
// blocks, far fewer points) and stays drawable; the budget holds throughout; a tile decoded again
// after a release is not counted twice in the patch detail; a tile loaded in part is decoded
// again for a view of a part its pieces do not cover; what the process holds while tiles decode
// (the C heap's bytes in use, decoding in flight and released points a snapshot still holds
// included) stays within tiny budgets, and a still camera stops loading.
#include <gtest/gtest.h>

#include <chrono>
#include <filesystem>
#include <map>
#include <thread>

#include "core/process_memory.hpp"
#include "dataset/dataset.hpp"
#include "test_data.hpp"
#include "viewer/point_sets.hpp"
#include "viewer/residency.hpp"
#include "survey_tiles.hpp"
#include "wait_until.hpp"

namespace lidarscout::viewer {
namespace {

using namespace std::chrono_literals;

dataset::Dataset jmo335() {
    return dataset::open_dataset({(test::surveys_dir() / "ky-jmo335-eastern-kentucky").string()});
}

using survey::tile_named;

render::Camera above(const dataset::Bounds& b, double height) {
    render::Camera c;
    c.x = b.centre_x(), c.y = b.centre_y(), c.z = b.max_z + height;
    c.pitch_deg = -90;
    c.width = 320, c.height = 240;
    c.near_m = 1, c.far_m = 1e5;
    return c;
}

// From 150 m above the middle of a tile, a narrow view that stays inside it down to the survey's
// lowest ground (its neighbours are not wanted).
render::Camera inside(const dataset::Bounds& b) {
    render::Camera c = above(b, 150);
    c.width = 60, c.height = 90;  // the view's half-width is 0.38 times its depth
    return c;
}

bool wait_idle(const Residency& r) {
    return test::wait_until([&] { return r.idle(); });
}

// Points held per tile, and the finest level held per tile.
std::map<std::uint32_t, std::pair<std::uint64_t, std::size_t>> held(const Residency& r) {
    std::map<std::uint32_t, std::pair<std::uint64_t, std::size_t>> out;
    for (const auto& b : r.blocks()) {
        auto& [points, levels] = out[b->tile];
        points += b->points.points.size();
        levels = std::max(levels, b->levels);
    }
    return out;
}

// Two decoding threads and a budget that holds tiles a and b (with the least their decoding
// holds, and their bookkeeping), but not both at full resolution.
ResidencyOptions one_at_a_time(const dataset::Dataset& ds, std::uint32_t a, std::uint32_t b) {
    const std::uint64_t bytes_a = tile_point_set_bytes(ds.tiles[a]), bytes_b = tile_point_set_bytes(ds.tiles[b]);
    const auto need = [&](std::uint32_t t) {
        const auto& tile = ds.tiles[t];
        return tile_point_set_bytes(tile) + decode_plan(tile, tile.tile.header.point_count, 2, 1).transient;
    };
    ResidencyOptions o;
    o.decode_threads = 2;
    o.memory_budget = std::max(need(a), need(b)) + std::min(bytes_a, bytes_b) / 2 + (2u << 20);
    return o;
}

// The three small tiles along the west edge of ky-jmo335.
std::vector<std::uint32_t> west_tiles(const dataset::Dataset& ds) {
    return {tile_named(ds, "N117E379"), tile_named(ds, "N118E379"), tile_named(ds, "N119E379")};
}

// Those seen from above at a distance, in a narrow view (about 180 m x 2.9 km: the middle column stays out of it).
render::Camera west_view(const dataset::Dataset& ds) {
    const auto west = west_tiles(ds);
    dataset::Bounds box = ds.tiles[west[0]].bounds_m;
    for (const auto t : west) box.extend(ds.tiles[t].bounds_m);
    render::Camera c = above(box, 2500);
    c.width = 30, c.height = 480;
    return c;
}

TEST(ViewerResidency, ATileThatMakesRoomKeepsItsCoarseLevels) {
    const auto ds = jmo335();
    const std::uint32_t a = tile_named(ds, "N117E379"), b = tile_named(ds, "N119E381");
    const std::uint64_t bytes_b = tile_point_set_bytes(ds.tiles[b]);
    const auto [ox, oy] = dataset::patch_grid_origin(ds);
    lidarscout::PatchGrid grid(ox, oy);
    ResidencyOptions o = one_at_a_time(ds, a, b);
    std::vector<std::pair<std::uint32_t, bool>> events;
    std::mutex mutex;
    o.on_tile = [&](std::uint32_t t, bool loaded) {
        std::lock_guard lock(mutex);
        events.emplace_back(t, loaded);
    };
    Residency r(ds, grid, o);
    r.start();
    r.set_camera(inside(ds.tiles[a].bounds_m));
    ASSERT_TRUE(wait_idle(r));
    auto h = held(r);
    ASSERT_TRUE(h.contains(a));
    EXPECT_EQ(h[a].first, ds.tiles[a].tile.header.point_count);
    EXPECT_EQ(h[a].second, kLodLevels);

    r.set_camera(inside(ds.tiles[b].bounds_m));
    ASSERT_TRUE(wait_idle(r));
    h = held(r);
    ASSERT_TRUE(h.contains(b));
    EXPECT_EQ(h[b].first, ds.tiles[b].tile.header.point_count);
    ASSERT_TRUE(h.contains(a)) << "the released tile kept nothing";
    EXPECT_GT(h[a].first, 0u);
    EXPECT_LT(h[a].first, ds.tiles[a].tile.header.point_count / 4);
    EXPECT_LT(h[a].second, kLodLevels);
    const auto st = r.stats();
    EXPECT_EQ(st.full_tiles, 1u);
    EXPECT_EQ(st.coarse_tiles, 1u);
    EXPECT_EQ(st.released, 1u);
    EXPECT_LE(st.bytes, o.memory_budget);
    EXPECT_LE(st.peak_bytes, o.memory_budget + 2 * bytes_b);
    std::lock_guard lock(mutex);
    const std::vector<std::pair<std::uint32_t, bool>> expected = {{a, true}, {a, false}, {b, true}};
    EXPECT_EQ(events, expected);
}

// The points behind the detail texels of the cells that tile `t` covers.
std::uint64_t detail_points(const Residency& r, const lidarscout::PatchGrid& grid, const dataset::Bounds& b) {
    std::uint64_t n = 0;
    const auto lo = grid.cell_of(b.min_x, b.min_y), hi = grid.cell_of(b.max_x, b.max_y);
    for (auto x = lo.ix; x <= hi.ix; ++x) {
        for (auto y = lo.iy; y <= hi.iy; ++y) {
            if (const auto d = r.detail({x, y})) {
                for (const auto c : d->all.count) n += c;
            }
        }
    }
    return n;
}

TEST(ViewerResidency, ATileReloadedAfterAReleaseIsNotFoldedIntoTheDetailTwice) {
    const auto ds = jmo335();
    const std::uint32_t a = tile_named(ds, "N117E379"), b = tile_named(ds, "N119E381");
    const auto [ox, oy] = dataset::patch_grid_origin(ds);
    lidarscout::PatchGrid grid(ox, oy);
    Residency r(ds, grid, one_at_a_time(ds, a, b));
    r.start();
    r.set_camera(inside(ds.tiles[a].bounds_m));
    ASSERT_TRUE(wait_idle(r));
    const std::uint64_t first = detail_points(r, grid, ds.tiles[a].bounds_m);
    EXPECT_EQ(first, ds.tiles[a].tile.header.point_count);
    r.set_camera(inside(ds.tiles[b].bounds_m));
    ASSERT_TRUE(wait_idle(r));
    r.set_camera(inside(ds.tiles[a].bounds_m));  // back: a is decoded again
    ASSERT_TRUE(wait_idle(r));
    EXPECT_EQ(held(r)[a].first, ds.tiles[a].tile.header.point_count);
    EXPECT_EQ(detail_points(r, grid, ds.tiles[a].bounds_m), first);
    EXPECT_EQ(r.stats().released, 2u);
}

// Small tiles only: the three along the west edge, seen from above at a distance. Each is a part of the view: while
// the least screen share wanted is nearly all of it (the scheduler raises it while chunk points load), none is.
TEST(ViewerResidency, EveryTileInViewEndsAtFullResolutionWhenTheBudgetAllows) {
    const auto ds = jmo335();
    const auto [ox, oy] = dataset::patch_grid_origin(ds);
    lidarscout::PatchGrid grid(ox, oy);
    ResidencyOptions o;
    o.decode_threads = 2;
    o.memory_budget = 2ull << 30;
    const std::vector<std::uint32_t> west = west_tiles(ds);
    Residency r(ds, grid, o);
    r.set_min_screen_fraction(0.95);
    r.start();
    r.set_camera(west_view(ds));
    ASSERT_TRUE(wait_idle(r));
    EXPECT_EQ(r.stats().wanted, 0u);
    EXPECT_EQ(r.stats().loads, 0u);
    EXPECT_TRUE(held(r).empty());
    r.set_min_screen_fraction(0);
    ASSERT_TRUE(wait_idle(r));
    const auto st = r.stats();
    EXPECT_EQ(st.wanted, 3u);
    EXPECT_EQ(st.wanted_full, st.wanted);
    EXPECT_TRUE(st.largest_full);
    const auto h = held(r);
    for (const auto t : west) {
        ASSERT_TRUE(h.contains(t)) << ds.tiles[t].tile.path();
        EXPECT_EQ(h.at(t).first, ds.tiles[t].tile.header.point_count);
    }
    EXPECT_LE(st.bytes, o.memory_budget);
}

TEST(ViewerResidency, ATileLargerThanTheBudgetDoesNotStopTheOthersAndLoadsInPart) {
    const auto ds = jmo335();
    const std::uint32_t big = tile_named(ds, "N118E380"), small = tile_named(ds, "N118E379");
    const auto [ox, oy] = dataset::patch_grid_origin(ds);
    lidarscout::PatchGrid grid(ox, oy);
    ResidencyOptions o;
    o.decode_threads = 2;
    o.memory_budget = 64ull << 20;  // the big tile's 142 MB never fit; the small one's 39 MB do
    ASSERT_GT(tile_point_set_bytes(ds.tiles[big]), o.memory_budget);
    ASSERT_LT(tile_point_set_bytes(ds.tiles[small]), o.memory_budget);
    // Over the big tile near their shared edge: a strip of the small one in view, so that the
    // big one improves the picture most per byte and comes first.
    dataset::Bounds edge = ds.tiles[big].bounds_m;
    edge.min_x += 340, edge.max_x = edge.min_x + 200;
    Residency r(ds, grid, o);
    r.start();
    r.set_camera(above(edge, 600));
    ASSERT_TRUE(wait_idle(r));
    // The small one loaded first (whole), then the big one in part: the pieces that fit in
    // the room there is, the small one down to its coarse levels for it (the big one covers
    // nearly all the image, so its bytes are worth more).
    auto h = held(r);
    ASSERT_TRUE(h.contains(small));
    EXPECT_GT(h[small].first, 0u);
    ASSERT_TRUE(h.contains(big));
    EXPECT_GT(h[big].first, 0u);
    EXPECT_LT(h[big].first, ds.tiles[big].tile.header.point_count / 2);
    const auto st = r.stats();
    EXPECT_EQ(st.wanted, 2u);
    EXPECT_LE(st.bytes, o.memory_budget);
    EXPECT_GT(st.bytes, o.memory_budget / 2) << "the room was not used";
}

// True when a block of `tile` held by `r` spans the point (x, y).
bool holds_point_at(const Residency& r, std::uint32_t tile, double x, double y) {
    for (const auto& b : r.blocks()) {
        const auto& box = b->bounds;
        if (b->tile == tile && box.min_x <= x && x <= box.max_x && box.min_y <= y && y <= box.max_y) return true;
    }
    return false;
}

TEST(ViewerResidency, APartlyLoadedTileIsDecodedAgainForAViewOfItsOtherPart) {
    const auto ds = jmo335();
    const std::uint32_t big = tile_named(ds, "N118E380");
    const auto [ox, oy] = dataset::patch_grid_origin(ds);
    lidarscout::PatchGrid grid(ox, oy);
    ResidencyOptions o;
    o.decode_threads = 2;
    o.memory_budget = 64ull << 20;  // under half of the big tile's 142 MB
    ASSERT_GT(tile_point_set_bytes(ds.tiles[big]), 2 * o.memory_budget);
    // Two views well inside the tile, its south-west and north-east quarters.
    const auto quarter = [&](double fx, double fy) {
        const auto& b = ds.tiles[big].bounds_m;
        dataset::Bounds q = b;
        const double w = b.max_x - b.min_x, h = b.max_y - b.min_y;
        q.min_x = b.min_x + fx * w, q.max_x = q.min_x + 0.1 * w;
        q.min_y = b.min_y + fy * h, q.max_y = q.min_y + 0.1 * h;
        return q;
    };
    const dataset::Bounds sw = quarter(0.2, 0.2), ne = quarter(0.7, 0.7);
    Residency r(ds, grid, o);
    r.start();
    r.set_camera(above(sw, 150));
    ASSERT_TRUE(wait_idle(r));
    EXPECT_TRUE(holds_point_at(r, big, sw.centre_x(), sw.centre_y()));
    ASSERT_FALSE(holds_point_at(r, big, ne.centre_x(), ne.centre_y())) << "the budget held that part already";

    r.set_camera(above(ne, 150));
    ASSERT_TRUE(wait_idle(r));
    EXPECT_TRUE(holds_point_at(r, big, ne.centre_x(), ne.centre_y())) << "the partly loaded tile was not loaded again";
    const auto st = r.stats();
    EXPECT_LE(st.bytes, o.memory_budget);
    EXPECT_GT(st.bytes, o.memory_budget / 2) << "the room was not used";
    // Still: nothing more to do, so the tile is not decoded over and over.
    const std::size_t released = st.released;
    std::this_thread::sleep_for(300ms);
    EXPECT_TRUE(r.idle());
    EXPECT_EQ(r.stats().released, released);
}

// Issue 16: the budget covers everything the residency holds for points, decoding in flight
// included (each decoding thread's records, points and block-building scratch), and blocks a
// release dropped while a snapshot still holds them. Tiny budgets over the whole survey (315 MB
// of points): while tiles stream, release and stream again, the C heap's bytes in use never grow
// past the budget (plus 15%, the limit, for the allocator's rounding); the residency's
// own count never passes the budget; a still camera ends idle and stops loading.
TEST(ViewerResidency, TinyBudgetsHoldWithDecodingInFlight) {
    const auto ds = jmo335();
    const auto [ox, oy] = dataset::patch_grid_origin(ds);
    for (const std::uint64_t mb : {24, 64}) {
        lidarscout::PatchGrid grid(ox, oy);
        ResidencyOptions o;
        o.decode_threads = 2;
        o.memory_budget = mb << 20;
        const std::uint64_t base = heap_use().in_use;
        std::uint64_t worst = 0;
        LodBlocks drawn;  // what a frame holds: the blocks of the last look, kept until the next
        {
            Residency r(ds, grid, o);
            r.start();
            r.set_camera(above(ds.bounds_m, 3000));
            const auto end = std::chrono::steady_clock::now() + 120s;
            while (!r.idle() && std::chrono::steady_clock::now() < end) {
                drawn = r.blocks();
                worst = std::max(worst, heap_use().in_use - std::min(base, heap_use().in_use));
                std::this_thread::sleep_for(2ms);
            }
            ASSERT_TRUE(r.idle()) << mb << " MB: not idle after 120 s";
            drawn.clear();
            const auto st = r.stats();
            EXPECT_LE(st.peak_bytes, o.memory_budget) << mb << " MB";
            EXPECT_GT(st.bytes, o.memory_budget / 2) << mb << " MB: the room was not used";
            EXPECT_GT(st.released, 0u) << mb << " MB: the survey fitted, the test checks nothing";
            // Still: no more loads.
            std::this_thread::sleep_for(500ms);
            EXPECT_TRUE(r.idle());
            EXPECT_EQ(r.stats().loads, st.loads) << mb << " MB: loading goes on for a still camera";
            std::printf("budget %llu MB: heap grew at most %llu MB; %zu loads, %zu releases\n",
                        (unsigned long long)mb, (unsigned long long)(worst >> 20), st.loads, st.released);
        }
        EXPECT_LE(worst, o.memory_budget + o.memory_budget * 15 / 100) << mb << " MB";
    }
}

}  // namespace
}  // namespace lidarscout::viewer
