// Drawing a snapshot: a heightmap under the camera fills the image, and each layer can be left
// out (nothing drawn without any, a few pixels for one chunk point alone); the points held by class,
// from the LOD blocks' counts, coarse copies counting only what they keep.
#include "viewer/scene_snapshot.hpp"

#include <gtest/gtest.h>

#include "render/framebuffer.hpp"
#include "viewer/cameras.hpp"
#include "viewer/point_lod.hpp"

namespace lidarscout::viewer {
namespace {

TEST(ViewerSchedulerSnapshot, LayersCanBeLeftOut) {
    PatchHeightmap h;
    h.origin_x = 1000, h.origin_y = 2000, h.texel_m = 10, h.size = 64;
    h.heights.assign(64 * 64, 50.0f);
    SceneSnapshot snapshot;
    snapshot.heightmaps = {share(std::move(h))};
    PointSet set;
    set.origin_x = 1320, set.origin_y = 2320, set.origin_z = 60;
    set.points.resize(1);
    snapshot.chunk_points = {std::make_shared<const PointSet>(set)};
    auto camera = test::looking_down(1320, 2320, 400);  // the 640 m patch fills the image
    camera.width = 64, camera.height = 48;
    ThreadPool pool(1);
    SceneStyle style;
    const auto all = render_snapshot(snapshot, camera, style, pool);
    EXPECT_EQ(all.drawn_pixels, 64u * 48u);
    SceneLayers none;
    none.heightmaps = none.chunk_points = none.full_points = false;
    EXPECT_EQ(render_snapshot(snapshot, camera, style, pool, none).drawn_pixels, 0u);
    SceneLayers points_only = none;
    points_only.chunk_points = true;
    const auto points = render_snapshot(snapshot, camera, style, pool, points_only);
    EXPECT_GT(points.drawn_pixels, 0u);
    EXPECT_LT(points.drawn_pixels, 20u);
}

TEST(ViewerSchedulerSnapshot, LoadedClassCountsSumTheBlocksHeld) {
    PointSet tile;
    tile.origin_x = 960, tile.origin_y = 1920;  // on the 80 m block grid
    for (int k = 0; k < 600; ++k) {             // two 80 m blocks, classes 2 and 6 and 200
        render::PointAttr a;
        a.dx = static_cast<float>((k * 7) % 160), a.dy = static_cast<float>((k * 13) % 80);
        a.classification = static_cast<std::uint8_t>(k % 3 == 0 ? 2 : k % 3 == 1 ? 6 : 200);
        tile.points.push_back(a);
    }
    ThreadPool pool(1);
    SceneSnapshot snapshot;
    snapshot.full_points = build_lod_blocks(tile, 0, 80, pool);
    ASSERT_EQ(snapshot.full_points.size(), 2u);
    auto counts = loaded_class_counts(snapshot);
    EXPECT_EQ(counts[2], 200u);
    EXPECT_EQ(counts[6], 200u);
    EXPECT_EQ(counts[200], 200u);
    EXPECT_EQ(counts[0], 0u);
    snapshot.full_points = {coarse_copy(*snapshot.full_points[0], 20.0)};  // a released tile's coarse levels
    counts = loaded_class_counts(snapshot);
    EXPECT_EQ(counts[2] + counts[6] + counts[200], snapshot.full_points[0]->points.points.size());
    EXPECT_LT(counts[2] + counts[6] + counts[200], 300u);
}

}  // namespace
}  // namespace lidarscout::viewer
