// Drawing a snapshot: a heightmap under the camera fills the image, and each layer can be left
// out (nothing drawn without any, a few pixels for one chunk point alone).
#include "viewer/scene_snapshot.hpp"

#include <gtest/gtest.h>

#include "render/framebuffer.hpp"
#include "viewer/cameras.hpp"

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

}  // namespace
}  // namespace lidarscout::viewer
