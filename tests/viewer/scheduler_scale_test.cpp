// The scheduler's bookkeeping follows the view, not the dataset: on virtual replicas of the nine
// ky-jmo335 tiles of 36 and 4,900 tiles, a close camera over the same spot of both, what a
// snapshot, the choice of the next heightmap job and the residency's look examine (patches, cell
// blocks, index nodes, tiles: counted, not timed) is alike, and a small part of the large one.
#include <gtest/gtest.h>

#include <chrono>
#include <thread>

#include "dataset/dataset.hpp"
#include "synth/replicate.hpp"
#include "temp_dir_fixture.hpp"
#include "test_data.hpp"
#include "viewer/scheduler.hpp"

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
    EXPECT_LT(l.job, l.patches / 20);
    EXPECT_LT(l.look, l.tiles / 20);
}

}  // namespace
}  // namespace lidarscout::viewer
