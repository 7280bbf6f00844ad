// Patch detail from full-resolution points: the per-texel means of a tile's points, merged
// count-weighted with another tile's, and laid over a heightmap where points fell; on a real
// survey seen whole, the points laid over the heightmaps show instead of the interpolated surface.
#include "viewer/patch_detail.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include <algorithm>

#include "dataset/chunk_point_loader.hpp"
#include "dataset/dataset.hpp"
#include "raster/dem.hpp"
#include "raster/gdal_test_util.hpp"
#include "render/framebuffer.hpp"
#include "temp_dir_fixture.hpp"
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

TEST(ViewerBareEarth, AFilterOfGroundOrWaterClassesAloneAsksForBareEarth) {
    const auto of = [](const char* classes, const char* returns = "") {
        return surface_of(PointFilter::parse(classes, returns, ""));
    };
    EXPECT_EQ(of(""), Surface::All);
    EXPECT_EQ(of("2"), Surface::Ground);
    EXPECT_EQ(of("2", "last"), Surface::Ground) << "returns do not change what the surface is";
    EXPECT_EQ(of("9"), Surface::Water);
    EXPECT_EQ(of("2,9"), Surface::GroundAndWater);
    EXPECT_EQ(of("2,6"), Surface::All) << "buildings are not bare earth";
    PointFilter none;
    none.classes.reset();
    EXPECT_EQ(surface_of(none), Surface::All);
    for (const auto& preset : filter_presets()) {
        if (preset.name == "ground") EXPECT_EQ(surface_of(preset.filter), Surface::Ground);
    }
}

TEST(ViewerBareEarth, TileDetailKeepsGroundAndWaterApart) {
    PointSet set;
    set.origin_x = kOx, set.origin_y = kOy;
    const auto point = [](float dx, float dy, float dz, std::uint8_t code) {
        render::PointAttr p;
        p.dx = dx, p.dy = dy, p.dz = dz, p.classification = code;
        return p;
    };
    set.points = {point(5, 5, 100, 2), point(6, 5, 102, 2), point(5, 6, 120, 5), point(15, 5, 90, 9)};
    const lidarscout::PatchGrid grid(kOx, kOy);
    const auto details = tile_detail(set, grid, 64);
    ASSERT_EQ(details.size(), 1u);
    const PatchDetail& d = details.begin()->second;
    EXPECT_EQ(d.all.count[0], 3u);
    EXPECT_NEAR(d.all.height[0], (100 + 102 + 120) / 3.0, 1e-4);
    ASSERT_FALSE(d.ground.empty());
    EXPECT_EQ(d.ground.count[0], 2u);
    EXPECT_NEAR(d.ground.height[0], 101.0, 1e-4);
    EXPECT_EQ(d.ground.count[1], 0u);
    ASSERT_FALSE(d.water.empty());
    EXPECT_EQ(d.water.count[1], 1u);
    EXPECT_EQ(d.water.count[0], 0u);
}

TEST(ViewerBareEarth, OverlayShowsGroundFillsHolesAndMarksWhatWasNotRead) {
    PatchHeightmap base;
    base.origin_x = kOx, base.origin_y = kOy, base.texel_m = 10, base.size = 4;
    base.heights.assign(16, 130.0f);  // the overview, roofs and canopy included
    PatchDetail d = detail_with(0, 125.0f, 3, render::pack_rgba(0, 200, 0));
    for (int t = 1; t < 12; ++t) d.all.height[t] = 125.0f, d.all.count[t] = 3;  // texels 0-11 were read
    d.ground = layer_with(0, 100.0f, 1, render::pack_rgba(90, 60, 30));
    for (int t = 1; t < 8; ++t) d.ground.height[t] = 100.0f, d.ground.count[t] = 1;
    const auto out = overlay_detail(base, d, Surface::Ground);
    EXPECT_EQ(out.surface, Surface::Ground);
    ASSERT_EQ(out.colours.size(), 16u) << "an untextured base gets grey colours to carry the marks";
    EXPECT_FLOAT_EQ(out.heights[3], 100.0f);       // ground points fell here
    EXPECT_NEAR(out.heights[9], 100.0f, 1e-3);     // read, no ground point: filled between the ground texels
    EXPECT_EQ(render::alpha(out.colours[9]), 255);
    EXPECT_FLOAT_EQ(out.heights[14], 130.0f);      // not read: the overview, marked
    EXPECT_EQ(render::alpha(out.colours[14]), kOverviewAlpha);
    EXPECT_EQ(out.view(Surface::Ground).tint, render::PatchTint::Marked);
    EXPECT_EQ(out.view(Surface::All).tint, render::PatchTint::All) << "bare earth where every point is wanted";
    EXPECT_EQ(base.view(Surface::Ground).tint, render::PatchTint::All) << "no detail: the overview, tinted whole";
    EXPECT_EQ(base.view(Surface::All).tint, render::PatchTint::None);
    const auto water = overlay_detail(base, d, Surface::Water);  // no water point: all read texels are holes
    EXPECT_EQ(render::alpha(water.colours[3]), kOverviewAlpha) << "nothing to fill from: the overview, marked";
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

class ViewerBareEarthSurvey : public test::TempDirTest {};

TEST_F(ViewerBareEarthSurvey, AGroundHeightmapAgreesWithATinDtmOfTheGroundPoints) {
    // IGN LiDAR HD, the two adjacent 1 km tiles around a bridge, classified: the detail a viewer gathers from
    // every point of it laid over as bare earth (Surface::Ground), against `dem --classes 2 --method
    // tin` at 1 m averaged over each 10 m texel (the texel's mean of ground points stands for the
    // same area). The control: the same detail laid over as every point (roofs and trees).
    ThreadPool pool(2);
    const auto dir = test::surveys_dir() / "ign-lidar-hd-1km";
    const auto ds = dataset::open_dataset({(dir / "test_semis_2023_0299_6802_LA93_IGN69.laz").string(),
                                           (dir / "test_semis_2023_0300_6802_LA93_IGN69.laz").string()});
    const lidarscout::PatchGrid grid(dataset::patch_grid_origin(ds).first, dataset::patch_grid_origin(ds).second);
    PatchDetails details;
    for (const auto& t : ds.tiles) {
        for (auto& [cell, d] : tile_detail(tile_point_set(t, ds.las_stride, pool), grid, 64)) {
            const auto [it, added] = details.try_emplace(cell, d);
            if (!added) merge_detail(it->second, d);
        }
    }
    raster::DemRequest r;
    r.output = path("dtm.tif");
    r.texel_m = 1.0;
    r.method = raster::DemMethod::Tin;
    r.filter = PointFilter::parse("2", "", "");
    r.threads = 2;
    const auto dem = raster::make_dem(ds, r);
    const auto tif = test::read_raster(r.output);
    ASSERT_FALSE(tif.values.empty());
    // The DEM's mean over the 1 m texels inside [x0, x0 + 10) x [y0, y0 + 10); NaN when none has a value.
    const auto dem_mean = [&](double x0, double y0) {
        double sum = 0;
        int n = 0;
        for (int dy = 0; dy < 10; ++dy) {
            for (int dx = 0; dx < 10; ++dx) {
                const int col = static_cast<int>(std::floor((x0 + dx + 0.5 - dem.grid.origin_x) / dem.grid.texel_m));
                const int south = static_cast<int>(std::floor((y0 + dy + 0.5 - dem.grid.origin_y) / dem.grid.texel_m));
                const int row = tif.height - 1 - south;
                if (col < 0 || row < 0 || col >= tif.width || row >= tif.height) continue;
                const float v = tif.at(row, col);
                if (std::isnan(v) || (tif.nodata && v == *tif.nodata)) continue;
                sum += v, ++n;
            }
        }
        return n ? sum / n : NAN;
    };
    std::vector<double> ground_err, filled_err, every_err;
    std::size_t marked = 0;
    for (const auto& [cell, d] : details) {
        PatchHeightmap base;  // no overview: only what the points say
        base.cell = cell, base.origin_x = d.origin_x, base.origin_y = d.origin_y, base.texel_m = d.texel_m;
        base.heights.assign(64 * 64, NAN);
        const auto bare = overlay_detail(base, d, Surface::Ground), every = overlay_detail(base, d, Surface::All);
        for (std::size_t t = 0; t < bare.heights.size(); ++t) {
            const double ref = dem_mean(d.origin_x + (t % 64) * d.texel_m, d.origin_y + (t / 64) * d.texel_m);
            if (std::isnan(ref) || std::isnan(bare.heights[t])) continue;
            if (render::alpha(bare.colours[t]) == kOverviewAlpha) ++marked;
            const double err = std::abs(bare.heights[t] - ref);
            (!d.ground.empty() && d.ground.count[t] > 0 ? ground_err : filled_err).push_back(err);
            every_err.push_back(std::abs(every.heights[t] - ref));
        }
    }
    const auto quantile = [](std::vector<double> v, double q) {
        std::sort(v.begin(), v.end());
        return v.empty() ? NAN : v[static_cast<std::size_t>(q * (v.size() - 1))];
    };
    std::printf("bare earth vs tin DTM: %zu ground texels median %.3f p95 %.3f m; %zu filled median %.3f p95 %.3f m; "
                "every point median %.3f p95 %.3f m; %zu marked\n",
                ground_err.size(), quantile(ground_err, 0.5), quantile(ground_err, 0.95), filled_err.size(),
                quantile(filled_err, 0.5), quantile(filled_err, 0.95), quantile(every_err, 0.5),
                quantile(every_err, 0.95), marked);
    ASSERT_GT(ground_err.size(), 10000u) << "2 km^2 at 10 m texels, most with ground points";
    // Measured: ground median 0.019, p95 0.147 m; filled (190 texels) median 0.156, p95 0.538 m;
    // every point p95 5.4 m. Bounds: a texel's ground mean within a decimetre or so of the TIN's
    // mean (the two stand for the same points), a filled hole within a metre (pull-push is not a TIN).
    ASSERT_FALSE(filled_err.empty()) << "the bridge's roads and trees leave texels without ground points";
    EXPECT_LT(quantile(ground_err, 0.5), 0.05);
    EXPECT_LT(quantile(ground_err, 0.95), 0.3);
    EXPECT_LT(quantile(filled_err, 0.95), 1.0);
    EXPECT_EQ(marked, 0u) << "every texel with a DTM height had points read";
    EXPECT_GT(quantile(every_err, 0.95), 5 * quantile(ground_err, 0.95)) << "the control: roofs and trees";
}

}  // namespace
}  // namespace lidarscout::viewer
