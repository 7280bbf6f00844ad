// The scheduler's bookkeeping follows the view, not the dataset: on virtual replicas of the nine
// ky-jmo335 tiles of 36 and 4,900 tiles, a close camera over the same spot of both, what a
// snapshot, the choice of the next heightmap job and the residency's look examine (patches, cell
// blocks, index nodes, tiles: counted, not timed) is alike, and a small part of the large one. And
// a replica whose heightmaps do not all fit the budget keeps it: the nearest built, the farthest let go. Its chunk
// points are drawn as a set per block of cells.
#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <thread>

#include "dataset/dataset.hpp"
#include "synth/replicate.hpp"
#include "temp_dir_fixture.hpp"
#include "test_data.hpp"
#include "viewer/cameras.hpp"
#include "viewer/cell_blocks.hpp"
#include "viewer/scheduler.hpp"
#include "wait_until.hpp"

namespace lidarscout::viewer {
namespace {

using namespace std::chrono_literals;

struct Work {
    std::uint64_t snapshot = 0, job = 0, look = 0;  // the largest seen of each
    std::size_t tiles_in_view = 0;
    std::size_t tiles = 0, patches = 0;
};

class SchedulerScale : public test::TempDirTest {
protected:
    dataset::Dataset replica(std::uint32_t side) {
        const auto out = dir / ("replica_" + std::to_string(side));
        const auto plan = synth::plan_replicas({(test::surveys_dir() / "ky-jmo335-eastern-kentucky").string()},
                                               out.string(), {side, side});
        synth::write_virtual_replica(plan);
        return dataset::open_dataset({(out / synth::kManifestName).string()});
    }

    // Looking 45 degrees down at a point 2 km into the replica from its south-west corner, from
    // 400 m away, moving a metre every frame (a moving camera makes every snapshot anew).
    static render::Camera close_view(const dataset::Dataset& ds, int frame) {
        render::Camera c;
        c.width = 640, c.height = 360;
        c.pitch_deg = -45, c.yaw_deg = 0;
        c.near_m = 1, c.far_m = 1e6;
        c.x = ds.bounds_m.min_x + 2000 + frame;
        c.y = ds.bounds_m.min_y + 2000 - 283;
        c.z = ds.bounds_m.max_z + 283;
        return c;
    }

    // Frames for `frames` x 20 ms while the scheduler loads; the largest work of each kind seen.
    static Work fly(const dataset::Dataset& ds, int frames) {
        SchedulerOptions o;
        o.cnn = false;
        o.memory_budget = 512ull << 20;
        o.decode_threads = 1;
        o.camera = close_view(ds, 0);
        Scheduler scheduler(ds, o);
        Work w;
        for (int f = 0; f < frames; ++f) {
            scheduler.set_camera(close_view(ds, f));
            (void)scheduler.snapshot();
            const auto st = scheduler.stats();
            w.snapshot = std::max(w.snapshot, st.snapshot_visits);
            w.job = std::max(w.job, st.job_visits);
            w.look = std::max(w.look, st.look_visits);
            w.tiles_in_view = std::max(w.tiles_in_view, st.tiles_in_view);
            w.patches = st.linear.total;
            std::this_thread::sleep_for(20ms);
        }
        w.tiles = ds.tiles.size();
        return w;
    }
};

TEST_F(SchedulerScale, WorkPerFrameAndTickFollowsTheView) {
    const auto small = replica(6), large = replica(70);
    ASSERT_EQ(small.tiles.size(), 36u);
    ASSERT_EQ(large.tiles.size(), 4900u);
    const Work s = fly(small, 150), l = fly(large, 150);
    ::testing::Test::RecordProperty("large_snapshot_visits", static_cast<int>(l.snapshot));
    std::printf("work per step, 36 / 4,900 tiles: snapshot %llu / %llu, heightmap job %llu / %llu, residency look "
                "%llu / %llu (tiles in view %zu / %zu; patches %zu / %zu)\n",
                static_cast<unsigned long long>(s.snapshot), static_cast<unsigned long long>(l.snapshot),
                static_cast<unsigned long long>(s.job), static_cast<unsigned long long>(l.job),
                static_cast<unsigned long long>(s.look), static_cast<unsigned long long>(l.look), s.tiles_in_view,
                l.tiles_in_view, s.patches, l.patches);
    // Something was seen and done, in both.
    ASSERT_GT(s.snapshot, 0u);
    ASSERT_GT(l.snapshot, 0u);
    ASSERT_GT(s.look, 0u);
    ASSERT_GT(l.look, 0u);
    ASSERT_GT(l.tiles_in_view, 0u);
    EXPECT_LE(l.tiles_in_view, s.tiles_in_view + 2) << "the same spot of both replicas";
    // Alike: a few more tree levels in the large one, nothing in proportion to its 136 times the tiles.
    EXPECT_LE(l.snapshot, 3 * s.snapshot + 64);
    EXPECT_LE(l.job, 3 * s.job + 2 * 256);  // a job looks at the ready cells of a block or two (256 each)
    EXPECT_LE(l.look, 3 * s.look + 64);
    // And a small part of the large dataset.
    EXPECT_LT(l.snapshot, l.patches / 20);
    EXPECT_LT(l.job, l.patches / 16);  // (the ready cells of the blocks nearest: 1,142-1,168 of 20,236 when chunk
                                        // points come as fast as a tile's are read, 6%)
    EXPECT_LT(l.look, l.tiles / 20);
}

bool wait_idle(const Scheduler& scheduler) {
    return test::wait_until([&] { return scheduler.idle(); });
}

// Whether the scheduler's picture shows a heightmap for the cell under (x, y).
bool heightmap_shown_at(const Scheduler& scheduler, double x, double y) {
    const CellKey cell = scheduler.grid().cell_of(x, y);
    for (const auto& h : scheduler.snapshot()->heightmaps) {
        if (h->cell == cell) return true;
    }
    return false;
}

TEST_F(SchedulerScale, HeightmapsKeepTheBudgetNearestFirst) {
    const auto ds = replica(6);
    const auto& b = ds.bounds_m;
    // The middles of the south-western and north-eastern tiles.
    const auto corner = [&](int sign) {
        const auto it = std::min_element(ds.tiles.begin(), ds.tiles.end(), [&](const auto& l, const auto& r) {
            return sign * (l.bounds_m.centre_x() + l.bounds_m.centre_y()) <
                   sign * (r.bounds_m.centre_x() + r.bounds_m.centre_y());
        });
        return std::pair{it->bounds_m.centre_x(), it->bounds_m.centre_y()};
    };
    const auto [near_x, near_y] = corner(1);
    const auto [far_x, far_y] = corner(-1);
    SchedulerOptions o;
    o.cnn = false, o.full_res = false;  // the heightmaps alone against the budget
    o.least_heightmaps = 16;  // of 131: the budget decides
    o.memory_budget = 1ull << 30;
    o.camera = test::looking_down(near_x, near_y, b.max_z + 400);
    std::size_t all = 0;
    std::uint64_t all_bytes = 0;
    {
        Scheduler everything(ds, o);
        ASSERT_TRUE(wait_idle(everything));
        everything.set_camera(test::looking_down(far_x, far_y, b.max_z + 400));
        ASSERT_TRUE(wait_idle(everything));
        EXPECT_TRUE(heightmap_shown_at(everything, far_x, far_y));
        EXPECT_TRUE(heightmap_shown_at(everything, near_x, near_y));
        const auto st = everything.stats();
        all = st.heightmaps_linear, all_bytes = st.bytes_used;
        EXPECT_EQ(st.heightmaps_let_go, 0u) << "room for all";
        EXPECT_EQ(st.linear.done, st.linear.total);
    }
    ASSERT_GT(all, 100u);
    o.memory_budget = all_bytes / 2;
    Scheduler scheduler(ds, o);
    ASSERT_TRUE(wait_idle(scheduler));
    auto st = scheduler.stats();
    std::printf("%zu heightmaps in %llu MiB; within %llu MiB: %zu held, %zu let go\n", all,
                static_cast<unsigned long long>(all_bytes >> 20),
                static_cast<unsigned long long>(o.memory_budget >> 20), st.heightmaps_linear, st.heightmaps_let_go);
    EXPECT_LE(st.bytes_used, o.memory_budget);
    EXPECT_GT(st.heightmaps_linear, all / 5);
    EXPECT_LT(st.heightmaps_linear, all * 3 / 5);
    EXPECT_TRUE(heightmap_shown_at(scheduler, near_x, near_y));

    // The opposite corner: its heightmaps come, the first corner's farthest go for them.
    scheduler.set_camera(test::looking_down(far_x, far_y, b.max_z + 400));
    ASSERT_TRUE(wait_idle(scheduler));
    st = scheduler.stats();
    EXPECT_LE(st.bytes_used, o.memory_budget);
    EXPECT_GT(st.heightmaps_let_go, 0u);
    EXPECT_TRUE(heightmap_shown_at(scheduler, far_x, far_y));

    // A larger budget: the rest are built once the camera moves again.
    scheduler.set_memory_budget(1ull << 30);
    scheduler.set_camera(test::looking_down(near_x, near_y, b.max_z + 400));
    ASSERT_TRUE(wait_idle(scheduler));
    st = scheduler.stats();
    EXPECT_EQ(st.heightmaps_linear, all);
    EXPECT_EQ(st.linear.done, st.linear.total) << "every patch tried, counted once";

    // A budget the chunk points alone fill: the nearest are held all the same, and stay.
    scheduler.set_memory_budget(64 << 10);
    scheduler.set_camera(test::looking_down(far_x, far_y, b.max_z + 400));
    ASSERT_TRUE(wait_idle(scheduler));
    std::this_thread::sleep_for(1s);  // a few looks at the room
    st = scheduler.stats();
    EXPECT_EQ(st.heightmaps_linear, o.least_heightmaps);
    EXPECT_TRUE(heightmap_shown_at(scheduler, far_x, far_y));
    const std::size_t let_go = st.heightmaps_let_go;
    std::this_thread::sleep_for(1s);
    EXPECT_EQ(scheduler.stats().heightmaps_let_go, let_go) << "a still view lets none go";
}

// A country's cells hold about nine chunk points each: they are drawn as one set per block of cells (not a set, a
// batch and a snapshot entry each), every chunk point once where the grid has it, but those under a heightmap.
TEST_F(SchedulerScale, ChunkPointsAreDrawnAsOneSetPerBlock) {
    const auto ds = replica(20);
    const auto& b = ds.bounds_m;
    SchedulerOptions o;
    o.cnn = false, o.full_res = false;
    o.least_heightmaps = 16;    // and no room for more: the rest show their chunk points
    o.memory_budget = 64 << 10;
    o.camera = render::Camera::looking_at_bounds(b.min_x, b.min_y, b.min_z, b.max_x, b.max_y, b.max_z, 640, 360, 60);
    Scheduler scheduler(ds, o);
    ASSERT_TRUE(test::wait_until([&] {
        const auto st = scheduler.stats();
        return st.tiles_loaded.done == st.tiles_loaded.total && st.heightmaps_linear >= o.least_heightmaps;
    }));
    const auto snap = scheduler.snapshot();
    const auto& grid = scheduler.grid();
    std::vector<CellKey> shown;
    for (const auto& h : snap->heightmaps) shown.push_back(h->cell);
    ASSERT_GE(shown.size(), 1u);

    struct Sums {
        std::uint64_t n = 0;
        double x = 0, y = 0, z = 0;
        void add(double px, double py, double pz) { ++n, x += px - 2e6, y += py - 1.3e6, z += pz; }
    } drawn, expected;
    for (const auto& set : snap->chunk_points) {
        for (const auto& p : set->points) drawn.add(set->origin_x + p.dx, set->origin_y + p.dy, set->origin_z + p.dz);
    }
    const std::vector<CellKey> cells = grid.cells();
    std::vector<CellKey> blocks;
    for (const CellKey cell : cells) {
        blocks.push_back(CellBlocks::key_of_cell(cell));
        if (std::find(shown.begin(), shown.end(), cell) != shown.end()) continue;
        for (const auto& p : grid.points_in(cell)) {
            const auto a = grid.to_absolute(cell, p);
            expected.add(a.x, a.y, a.z);
        }
    }
    sort_cells(blocks);
    blocks.erase(std::unique(blocks.begin(), blocks.end()), blocks.end());
    std::printf("%zu chunk points in %zu cells, %zu blocks: %zu sets drawn\n", grid.size(), cells.size(),
                blocks.size(), snap->chunk_points.size());
    ASSERT_GT(expected.n, 0u);
    EXPECT_LT(expected.n, grid.size()) << "the heightmaps' cells left out";
    EXPECT_EQ(drawn.n, expected.n);
    const double n = static_cast<double>(expected.n);
    EXPECT_NEAR(drawn.x, expected.x, n * 2e-3);  // (float offsets within a 10 km block: about a millimetre)
    EXPECT_NEAR(drawn.y, expected.y, n * 2e-3);
    EXPECT_NEAR(drawn.z, expected.z, n * 2e-3);
    EXPECT_LE(snap->chunk_points.size(), blocks.size());
    EXPECT_GT(cells.size(), 8 * blocks.size());
}

}  // namespace
}  // namespace lidarscout::viewer
