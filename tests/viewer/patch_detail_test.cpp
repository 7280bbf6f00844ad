// Patch detail from full-resolution points: the per-texel means of a tile's points, merged
// count-weighted with another tile's, and laid over a heightmap where points fell; on a real
// survey seen whole, the points laid over the heightmaps show instead of the interpolated surface.
#include "viewer/patch_detail.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "dataset/chunk_point_loader.hpp"
#include "dataset/dataset.hpp"
#include "render/framebuffer.hpp"
#include "test_data.hpp"
#include "viewer/heightmap_builder.hpp"
#include "viewer/scene.hpp"
#include "viewer/visibility.hpp"

namespace lidarscout::viewer {
namespace {

constexpr double kOx = 500'000.0, kOy = 4'000'000.0;

DetailLayer layer_with(int texel, float height, std::uint32_t count, std::uint32_t colour) {
    DetailLayer l;
    l.height.assign(16, NAN), l.count.assign(16, 0), l.colour.assign(16, 0);
    l.height[texel] = height, l.count[texel] = count, l.colour[texel] = colour;
    return l;
}

PatchDetail detail_with(int texel, float height, std::uint32_t count, std::uint32_t colour) {
    PatchDetail d;
    d.origin_x = kOx, d.origin_y = kOy, d.texel_m = 10, d.size = 4;
    d.all = layer_with(texel, height, count, colour);
    return d;
}

TEST(ViewerSchedulerDetail, MergeIsTheCountWeightedMean) {
    auto a = detail_with(5, 10.0f, 1, render::pack_rgba(0, 0, 0));
    const auto b = detail_with(5, 20.0f, 3, render::pack_rgba(200, 100, 40));
    merge_detail(a, b);
    EXPECT_FLOAT_EQ(a.all.height[5], 17.5f);
    EXPECT_EQ(a.all.count[5], 4u);
    EXPECT_NEAR(render::red(a.all.colour[5]), 150, 1);
    EXPECT_TRUE(std::isnan(a.all.height[0]));
    merge_detail(a, detail_with(0, 3.0f, 2, render::pack_rgba(1, 2, 3)));  // a texel only the other has
    EXPECT_FLOAT_EQ(a.all.height[0], 3.0f);
    EXPECT_EQ(a.all.count[0], 2u);
    EXPECT_TRUE(a.ground.empty()) << "neither had ground points";
    auto g = detail_with(1, 7.0f, 1, 0);
    g.ground = layer_with(1, 7.0f, 1, 0);
    merge_detail(a, g);  // a ground layer the cell had none of
    ASSERT_FALSE(a.ground.empty());
    EXPECT_FLOAT_EQ(a.ground.height[1], 7.0f);
    EXPECT_GT(a.bytes(), a.all.bytes());
}

TEST(ViewerSchedulerDetail, OverlayReplacesOnlyTexelsWithPoints) {
    PatchHeightmap base;
    base.origin_x = kOx, base.origin_y = kOy, base.texel_m = 10, base.size = 4;
    base.heights.assign(16, 1.0f);
    base.colours.assign(16, render::pack_rgba(9, 9, 9));
    const auto out = overlay_detail(base, detail_with(6, 42.0f, 5, render::pack_rgba(200, 0, 0)));
    EXPECT_FLOAT_EQ(out.heights[6], 42.0f);
    EXPECT_EQ(render::red(out.colours[6]), 200);
    EXPECT_FLOAT_EQ(out.heights[7], 1.0f);
    EXPECT_EQ(render::red(out.colours[7]), 9);
}

// Of the pixels where `points` (the points alone) drew something, the share where `frame` shows
// the same colour: there a point won over the surface.
double share_from_points(const render::RgbaImage& points, const render::RgbaImage& frame, std::uint32_t background) {
    std::size_t drawn = 0, same = 0;
    for (std::size_t i = 0; i < points.pixels.size(); ++i) {
        if (points.pixels[i] == background) continue;
        ++drawn;
        same += frame.pixels[i] == points.pixels[i];
    }
    return drawn ? static_cast<double>(same) / static_cast<double>(drawn) : 0.0;
}

// A survey as `render --until full` draws it at the auto camera: chunk points, linear heightmaps
// of the visible patches and every tile's points.
struct WholeSurvey {
    dataset::Dataset ds;
    lidarscout::PatchGrid grid;
    render::Camera camera;
    std::vector<PatchHeightmap> heightmaps;
    std::vector<PointSet> chunk_points, full_points;

    WholeSurvey(const std::string& name, ThreadPool& pool)
        : ds(dataset::open_dataset({(test::surveys_dir() / name).string()})),
          grid(dataset::patch_grid_origin(ds).first, dataset::patch_grid_origin(ds).second) {
        const auto& b = ds.bounds_m;
        camera = render::Camera::looking_at_bounds(b.min_x, b.min_y, b.min_z, b.max_x, b.max_y, b.max_z, 640, 360);
        dataset::ChunkPointLoader loader(ds, grid);
        loader.start();
        loader.wait();
        const auto cells = visible_cells(grid, camera, b.min_z, b.max_z);
        HeightmapBuildOptions options;
        options.patch.has_rgb = chunk_points_have_rgb(grid);
        options.footprints = tile_footprints(ds);
        heightmaps = build_linear_heightmaps(grid, cells, options, pool);
        chunk_points = overview_point_sets(grid, cells, heightmaps);
        for (const auto& t : ds.tiles) full_points.push_back(tile_point_set(t, ds.las_stride, pool));
    }

    render::RgbaImage draw(std::span<const PatchHeightmap> surface, ThreadPool& pool) const {
        std::vector<render::HeightmapPatch> patches;
        for (const auto& h : surface) patches.push_back(h.view());
        SceneStyle style;
        style.colour = colour_settings(render::ColourMode::Rgb, ds.bounds_m.min_z, ds.bounds_m.max_z);
        return draw_scene_frame(camera, patches, batches_of(chunk_points), batches_of(full_points), style, pool).image;
    }
};

TEST(ViewerSchedulerDetail, OnARealSurveyThePointsShowOverTheSurface) {
    // ky-jmo335 seen whole: 319 chunk points interpolated over 6 km^2 of wooded valleys lie metres
    // above the roads and fields in them; drawn as they are (the control) they hide those points.
    ThreadPool pool(2);
    WholeSurvey survey("ky-jmo335-eastern-kentucky", pool);
    ASSERT_FALSE(survey.heightmaps.empty());
    ASSERT_EQ(survey.full_points.size(), survey.ds.tiles.size());
    const std::uint32_t background = render::ResolveSettings{}.background;
    const auto points = survey.draw({}, pool);
    const double interpolated = share_from_points(points, survey.draw(survey.heightmaps, pool), background);
    auto overlaid = survey.heightmaps;
    overlay_points(overlaid, survey.full_points, survey.grid);
    const double laid_over = share_from_points(points, survey.draw(overlaid, pool), background);
    std::printf("pixels from points: %.3f with the points laid over the heightmaps, %.3f without\n", laid_over,
                interpolated);
    EXPECT_GE(laid_over, 0.95);
    EXPECT_LT(interpolated, laid_over - 0.05) << "the control: the interpolated surface hides points";
}

}  // namespace
}  // namespace lidarscout::viewer
