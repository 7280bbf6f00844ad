// FrameRefiner: a frame that changes nothing since the last one (for the settling time) is
// refined once (every point held), then given back as is; a camera move, or a new snapshot while
// points load, goes back to the LOD frame; new data once nothing loads is drawn refined at once;
// while points load nothing is refined until the snapshot stays unchanged; new data for a still
// view is drawn at most every interval.
// refined_spacing: every point under the cap, finer fractions of the LOD spacing above it.
#include <gtest/gtest.h>

#include <random>
#include <thread>

#include "viewer/frame_refiner.hpp"

namespace lidarscout::viewer {
namespace {

// 200 000 random points over 160 m x 80 m, as LOD blocks in a snapshot.
std::shared_ptr<SceneSnapshot> random_snapshot() {
    std::mt19937 rng(3);
    std::uniform_real_distribution<float> x(0, 159.9f), y(0, 79.9f), z(0, 5);
    PointSet set;
    for (int i = 0; i < 200000; ++i) {
        render::PointAttr p;
        p.dx = x(rng), p.dy = y(rng), p.dz = z(rng);
        p.r = p.g = p.b = static_cast<std::uint8_t>(rng());
        set.points.push_back(p);
    }
    ThreadPool pool(1);
    auto snap = std::make_shared<SceneSnapshot>();
    snap->full_points = build_lod_blocks(set, 0, 80, pool);
    snap->version = 1;
    return snap;
}

render::Camera overhead() {
    render::Camera c;
    c.x = 80, c.y = 40, c.z = 400;
    c.pitch_deg = -90;
    c.width = 320, c.height = 240;
    c.near_m = 1;
    return c;
}

TEST(ViewerFrameRefiner, StillFramesAreRefinedOnceThenKept) {
    const auto snap = random_snapshot();
    ThreadPool pool(2);
    SceneStyle style;
    FrameRefiner refiner(std::chrono::milliseconds(0), 24'000'000, std::chrono::milliseconds(0));
    render::Camera camera = overhead();
    const auto first = refiner.draw(*snap, camera, style, pool);
    EXPECT_FALSE(refiner.refined());
    const auto second = refiner.draw(*snap, camera, style, pool);
    EXPECT_TRUE(refiner.refined());
    style.lod_spacing_px = 0;
    const auto all = render_snapshot(*snap, camera, style, pool);
    EXPECT_EQ(second.image.pixels, all.image.pixels);
    EXPECT_NE(first.image.pixels, all.image.pixels) << "the LOD frame already drew every point";
    style.lod_spacing_px = SceneStyle{}.lod_spacing_px;
    const RenderedScene* kept = &refiner.draw(*snap, camera, style, pool);
    EXPECT_TRUE(refiner.refined());
    EXPECT_EQ(kept->image.pixels, all.image.pixels);

    camera.x += 1;
    refiner.draw(*snap, camera, style, pool);
    EXPECT_FALSE(refiner.refined());
    refiner.draw(*snap, camera, style, pool);
    EXPECT_TRUE(refiner.refined());
    auto changed = std::make_shared<SceneSnapshot>(*snap);
    changed->version = 2;
    refiner.draw(*changed, camera, style, pool, {}, true);
    EXPECT_FALSE(refiner.refined()) << "new data while points load";
    changed->version = 3;
    refiner.draw(*changed, camera, style, pool);
    EXPECT_TRUE(refiner.refined()) << "new data once nothing loads";
}

TEST(ViewerFrameRefiner, NothingIsRefinedWhilePointsLoadUntilTheSnapshotSettles) {
    const auto snap = random_snapshot();
    ThreadPool pool(2);
    FrameRefiner refiner(std::chrono::milliseconds(0), 24'000'000, std::chrono::milliseconds(0),
                         std::chrono::milliseconds(300));
    const render::Camera camera = overhead();
    for (int i = 0; i < 3; ++i) {
        refiner.draw(*snap, camera, {}, pool, {}, true);
        EXPECT_FALSE(refiner.refined()) << "frame " << i;
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(350));  // loading, but nothing new came
    refiner.draw(*snap, camera, {}, pool, {}, true);
    EXPECT_TRUE(refiner.refined());

    FrameRefiner ending(std::chrono::milliseconds(0), 24'000'000, std::chrono::milliseconds(0),
                        std::chrono::milliseconds(60'000));
    ending.draw(*snap, camera, {}, pool, {}, true);
    ending.draw(*snap, camera, {}, pool, {}, true);
    EXPECT_FALSE(ending.refined());
    ending.draw(*snap, camera, {}, pool, {}, false);  // the last tile came in
    EXPECT_TRUE(ending.refined());
}

TEST(ViewerFrameRefiner, RefinesOnlyOnceSettled) {
    const auto snap = random_snapshot();
    ThreadPool pool(2);
    FrameRefiner refiner(std::chrono::milliseconds(200));
    const render::Camera camera = overhead();
    refiner.draw(*snap, camera, {}, pool);
    refiner.draw(*snap, camera, {}, pool);
    EXPECT_FALSE(refiner.refined());
    std::this_thread::sleep_for(std::chrono::milliseconds(250));
    refiner.draw(*snap, camera, {}, pool);
    EXPECT_TRUE(refiner.refined());
}

TEST(ViewerFrameRefiner, DataArrivingForAStillViewIsDrawnAtMostEveryInterval) {
    const auto snap = random_snapshot();
    ThreadPool pool(2);
    FrameRefiner refiner(std::chrono::milliseconds(0), 24'000'000, std::chrono::milliseconds(150));
    render::Camera camera = overhead();
    refiner.draw(*snap, camera, {}, pool);
    refiner.draw(*snap, camera, {}, pool);
    ASSERT_TRUE(refiner.refined());
    auto changed = std::make_shared<SceneSnapshot>();  // new data: nothing drawn any more
    changed->version = 2;
    const auto& kept = refiner.draw(*changed, camera, {}, pool, {}, true);
    EXPECT_TRUE(refiner.refined()) << "redrawn within the interval";
    EXPECT_GT(kept.drawn_pixels, 0u);
    std::this_thread::sleep_for(std::chrono::milliseconds(1000));  // past the interval and 9 draw times
    const auto& fresh = refiner.draw(*changed, camera, {}, pool, {}, true);
    EXPECT_FALSE(refiner.refined());
    EXPECT_EQ(fresh.drawn_pixels, 0u);
    camera.x += 1;  // a moving camera is never held back
    changed->version = 3;
    refiner.draw(*snap, camera, {}, pool);
    EXPECT_FALSE(refiner.refined());
    EXPECT_GT(refiner.draw(*snap, camera, {}, pool).drawn_pixels, 0u);
}

TEST(ViewerFrameRefiner, RefinedSpacingStaysUnderThePointCap) {
    const auto snap = random_snapshot();
    const render::Camera camera = overhead();
    EXPECT_EQ(refined_spacing(snap->full_points, camera, 0.5, 200000), 0.0);
    const double s = refined_spacing(snap->full_points, camera, 0.5, 100000);
    EXPECT_GT(s, 0.0);
    EXPECT_LE(s, 0.5);
    std::uint64_t n = 0;
    for (const auto& b : lod_batches(snap->full_points, camera, s)) n += b.points.size();
    EXPECT_LE(n, 100000u);
    EXPECT_EQ(refined_spacing(snap->full_points, camera, 0.5, 10), 0.5);
}

}  // namespace
}  // namespace lidarscout::viewer
