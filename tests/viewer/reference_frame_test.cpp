// Reference frames on a real survey: streaming the visible tiles piece by piece into one
// framebuffer gives the same picture as drawing every point of every tile at once (the
// all-points reference), for a view of part of the survey (uncoloured: grey as the scheduler paints); the cache gives
// back what was stored under the same key, nothing for another camera, and nothing for a damaged file.
#include "viewer/reference_frame.hpp"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "dataset/dataset.hpp"
#include "render/image_compare.hpp"
#include "survey_tiles.hpp"
#include "temp_dir_fixture.hpp"
#include "test_data.hpp"
#include "viewer/point_sets.hpp"
#include "viewer/scene.hpp"

namespace lidarscout::viewer {
namespace {

// Four strips of 0.5-0.9 M points each, stacked south to north, without colour (drawn grey).
dataset::Dataset strips() { return dataset::open_dataset({(test::surveys_dir() / "lasr-bcts-strips").string()}); }

// Straight down at the line between the first two strips, from about 160 m above them: the
// other two are out of view.
render::Camera strips_view(const dataset::Dataset& ds) {
    const auto& b = ds.tiles[survey::tile_named(ds, "bcts_1")].bounds_m;
    render::Camera c;
    c.width = 200, c.height = 150;
    c.pitch_deg = -90;
    c.near_m = 1, c.far_m = 1e5;
    c.x = b.centre_x(), c.y = b.max_y, c.z = b.max_z + 140;
    return c;
}

TEST(ViewerReferenceFrame, StreamingEqualsDrawingEveryPointAtOnce) {
    const auto ds = strips();
    const render::Camera camera = strips_view(ds);
    SceneStyle style;
    style.resolve.edl_strength = 0;
    ThreadPool pool(2);
    std::uint64_t last_done = 0, total = 0;
    const auto streamed = stream_reference_frame(
        ds, camera, {}, style, pool,
        [&](std::uint64_t done, std::uint64_t all) { last_done = std::max(last_done, done), total = all; });
    // Every point of every tile of the survey, visible or not, drawn at once.
    Scene all;
    std::uint64_t survey_points = 0;
    for (const auto& t : ds.tiles) {
        all.full_points.push_back(tile_point_set(t, ds.las_stride, pool));
        survey_points += t.tile.header.point_count;
    }
    ASSERT_FALSE(survey_has_rgb(ds));
    paint_uncoloured(all.full_points);
    const auto reference = render_scene(all, camera, style, pool).image;
    ASSERT_EQ(streamed.width, reference.width);
    EXPECT_EQ(streamed.pixels, reference.pixels) << render::image_psnr_db(streamed, reference) << " dB";
    EXPECT_EQ(last_done, total);
    EXPECT_GT(total, 0u);
    EXPECT_LT(total, survey_points) << "the view sees every tile: the test does not check the choice of tiles";
    std::size_t background = 0;
    for (const auto p : streamed.pixels) background += p == style.resolve.background;
    EXPECT_LT(background, streamed.pixels.size() / 2) << "the view shows too few points to compare";
}

class ViewerReferenceCache : public test::TempDirTest {};

TEST_F(ViewerReferenceCache, GivesBackWhatWasStoredUnderItsKeyOnly) {
    const auto ds = strips();
    const SceneStyle style;
    render::Camera camera = strips_view(ds);
    const std::string key = reference_key(ds, camera, style, "test");
    render::RgbaImage image;
    image.width = 3, image.height = 2;
    image.pixels = {1, 2, 3, 4, 5, 0xffffffffu};
    EXPECT_FALSE(load_reference(dir, key));
    store_reference(dir / "made", key, image);
    const auto back = load_reference(dir / "made", key);
    ASSERT_TRUE(back);
    EXPECT_EQ(back->width, 3);
    EXPECT_EQ(back->pixels, image.pixels);
    EXPECT_EQ(reference_key(ds, camera, style, "test"), key);
    EXPECT_NE(reference_key(ds, camera, style, "other heightmaps"), key);
    camera.x += 1;
    EXPECT_NE(reference_key(ds, camera, style, "test"), key);
    // A damaged file is not a reference.
    for (const auto& entry : std::filesystem::directory_iterator(dir / "made")) {
        std::filesystem::resize_file(entry.path(), std::filesystem::file_size(entry.path()) - 1);
    }
    EXPECT_FALSE(load_reference(dir / "made", key));
}

}  // namespace
}  // namespace lidarscout::viewer
