// Heightmap pass: coverage of a patch seen from above, seams between patches, NaN holes, the
// depth bias against points, elevation colours, shading, LOD and culling.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "core/error.hpp"
#include "render/heightmap_pass.hpp"
#include "render/point_pass.hpp"

namespace lidarscout::render {
namespace {

constexpr double kX0 = 500'000.0, kY0 = 4'000'000.0;

struct OwnedPatch {
    double origin_x = kX0, origin_y = kY0, texel_m = 10.0;
    int size = 64;
    std::vector<float> heights;
    std::vector<std::uint32_t> colours;
    PatchTint tint = PatchTint::None;

    HeightmapPatch view() const { return {origin_x, origin_y, texel_m, size, heights, colours, 0, tint}; }
    float& height(int row, int col) { return heights[static_cast<std::size_t>(row) * size + col]; }
};

OwnedPatch flat_patch(double origin_x, double origin_y, float height, std::uint32_t colour, int size = 64) {
    OwnedPatch p;
    p.origin_x = origin_x;
    p.origin_y = origin_y;
    p.size = size;
    p.heights.assign(static_cast<std::size_t>(size) * size, height);
    p.colours.assign(p.heights.size(), colour);
    return p;
}

Camera top_down(double x, double y, double z, int size = 256) {
    Camera c;
    c.x = x, c.y = y, c.z = z;
    c.pitch_deg = -90;
    c.width = c.height = size;
    return c;
}

// The pass's settings with the outline left empty: what the triangles cover, pixel centres inside.
HeightmapPassSettings centres_only() {
    HeightmapPassSettings s;
    s.fill_outline = false;
    return s;
}

Framebuffer render(const Camera& c, const std::vector<OwnedPatch>& owned,
                   const HeightmapPassSettings& s = centres_only()) {
    std::vector<HeightmapPatch> patches;
    for (const OwnedPatch& p : owned) patches.push_back(p.view());
    Framebuffer fb(c.width, c.height);
    ThreadPool pool(3);
    draw_heightmaps(fb, c, patches, s, pool);
    return fb;
}

ScreenPoint projected(const Camera& c, double x, double y, double z) {
    const auto p = c.project(x, y, z);
    EXPECT_TRUE(p.has_value());
    return p.value_or(ScreenPoint{});
}

// Whether (px, py) lies inside the convex quad q (either winding) by more than `margin` px
// (> 0) or outside it by more than -margin (< 0 asks "clearly outside").
bool inside_quad(const std::array<ScreenPoint, 4>& q, float px, float py, float margin) {
    int positive = 0, negative = 0;
    for (int i = 0; i < 4; ++i) {
        const ScreenPoint a = q[i], b = q[(i + 1) % 4];
        const float len = std::hypot(b.x - a.x, b.y - a.y);
        const float d = ((b.x - a.x) * (py - a.y) - (b.y - a.y) * (px - a.x)) / len;
        positive += d > margin;
        negative += d < -margin;
    }
    return positive == 4 || negative == 4;
}

// The screen quad of the rectangle [x0, x1] x [y0, y1] at height z.
std::array<ScreenPoint, 4> screen_quad(const Camera& c, double x0, double y0, double x1, double y1, double z) {
    return {projected(c, x0, y0, z), projected(c, x1, y0, z), projected(c, x1, y1, z), projected(c, x0, y1, z)};
}

// Counts pixels clearly inside the quad that are empty, and clearly outside that are drawn.
struct CoverageErrors {
    int inside = 0, holes = 0, spill = 0;
};
CoverageErrors check_coverage(const Framebuffer& fb, const std::array<ScreenPoint, 4>& q) {
    CoverageErrors e;
    for (int y = 0; y < fb.height(); ++y) {
        for (int x = 0; x < fb.width(); ++x) {
            const float cx = x + 0.5f, cy = y + 0.5f;
            if (inside_quad(q, cx, cy, 0.01f)) {
                ++e.inside;
                e.holes += fb.empty_at(x, y);
            } else if (!inside_quad(q, cx, cy, -0.01f)) {
                e.spill += !fb.empty_at(x, y);
            }
        }
    }
    return e;
}

TEST(RenderHeightmapPass, FlatPatchFromAboveCoversItsRectangle) {
    const OwnedPatch patch = flat_patch(kX0, kY0, 100.0f, pack_rgba(180, 120, 60));
    const Camera c = top_down(kX0 + 300.0, kY0 + 330.0, 1100.0);
    const Framebuffer fb = render(c, {patch});
    const CoverageErrors e = check_coverage(fb, screen_quad(c, kX0, kY0, kX0 + 640, kY0 + 640, 100.0));
    EXPECT_GT(e.inside, 130 * 130);
    EXPECT_EQ(e.holes, 0);
    EXPECT_EQ(e.spill, 0);
    // Level ground shows its texture's own colour (the colour of the points it stands for).
    const HeightmapPassSettings s;
    const std::uint64_t centre = fb.at(128, 128);
    EXPECT_NEAR(red(fragment_rgba(centre)), 180, 1.0);
    EXPECT_NEAR(green(fragment_rgba(centre)), 120, 1.0);
    EXPECT_NEAR(blue(fragment_rgba(centre)), 60, 1.0);
    EXPECT_NEAR(fragment_depth(centre), 1000.0f * (1.0f + s.depth_bias), 0.01);
}

TEST(RenderHeightmapPass, CoarseLevelOfDetailLeavesNoHoles) {
    // 62 texels: the last block of a step-4 grid is 2 texels wide.
    const OwnedPatch patch = flat_patch(kX0, kY0, 50.0f, pack_rgba(90, 90, 90), 62);
    const Camera c = top_down(kX0 + 290.0, kY0 + 330.0, 6050.0, 512);
    ASSERT_EQ(lod_step(patch.view(), 50.0, 50.0, c, HeightmapPassSettings{}.lod_quad_px), 4);
    const Framebuffer fb = render(c, {patch});
    const CoverageErrors e = check_coverage(fb, screen_quad(c, kX0, kY0, kX0 + 620, kY0 + 620, 50.0));
    EXPECT_GT(e.inside, 40 * 40);
    EXPECT_EQ(e.holes, 0);
    EXPECT_EQ(e.spill, 0);
}

TEST(RenderHeightmapPass, CoarseBlocksWithUndefinedTexelsStillDrawTheirDefinedPart) {
    // Defined: 37 columns by 50 rows, neither on the step-16 grid (a patch on the edge of the data).
    OwnedPatch patch = flat_patch(kX0, kY0, 50.0f, pack_rgba(90, 90, 90));
    for (int row = 0; row < patch.size; ++row) {
        for (int col = 0; col < patch.size; ++col) {
            if (row >= 50 || col >= 37) patch.height(row, col) = std::nanf("");
        }
    }
    const Camera c = top_down(kX0 + 320.0, kY0 + 320.0, 6050.0, 512);
    HeightmapPassSettings s = centres_only();
    s.lod_quad_px = 12.0f;
    ASSERT_EQ(lod_step(patch.view(), 50.0, 50.0, c, s.lod_quad_px), 16);
    const CoverageErrors e =
        check_coverage(render(c, {patch}, s), screen_quad(c, kX0, kY0, kX0 + 370, kY0 + 500, 50.0));
    EXPECT_GT(e.inside, 25 * 35);
    EXPECT_EQ(e.holes, 0);  // the blocks cut by the edge were once dropped whole
    EXPECT_EQ(e.spill, 0);
}

TEST(RenderHeightmapPass, FromAfarTheOutlineIsFilledLikePointsFillIt) {
    // 640 m at 1,750 m: the patch is 40.5 px wide, its edges a quarter pixel beyond pixel centres.
    const double x0 = kX0 + 0.32, y0 = kY0 + 9.68;
    const OwnedPatch patch = flat_patch(x0, y0, 50.0f, pack_rgba(90, 90, 90));
    const Camera c = top_down(kX0 + 320.0, kY0 + 330.0, 1800.0, 128);
    const auto q = screen_quad(c, x0, y0, x0 + 640.0, y0 + 640.0, 50.0);
    const Framebuffer exact = render(c, {patch});
    const Framebuffer filled = render(c, {patch}, HeightmapPassSettings{});
    int touched = 0, touched_empty = 0, outline = 0, beyond = 0;
    for (int y = 0; y < c.height; ++y) {
        for (int x = 0; x < c.width; ++x) {
            const float cx = x + 0.5f, cy = y + 0.5f;
            if (inside_quad(q, cx, cy, -0.45f)) {  // the pixel's square reaches into the patch
                ++touched;
                touched_empty += filled.empty_at(x, y);
                outline += exact.empty_at(x, y);
            } else if (!inside_quad(q, cx, cy, -1.55f)) {
                beyond += !filled.empty_at(x, y);  // fills do not spread
            }
        }
    }
    EXPECT_GT(outline, 4 * 40);  // the triangles alone leave the outline empty
    EXPECT_GE(touched, 42 * 42);
    EXPECT_EQ(touched_empty, 0);
    EXPECT_EQ(beyond, 0);
}

TEST(RenderHeightmapPass, AdjacentPatchesLeaveNoGap) {
    const std::vector<OwnedPatch> patches = {flat_patch(kX0, kY0, 100.0f, pack_rgba(200, 0, 0)),
                                             flat_patch(kX0 + 640.0, kY0, 100.0f, pack_rgba(0, 0, 200))};
    Camera c;
    c.x = kX0 + 600.0, c.y = kY0 - 700.0, c.z = 1300.0;
    c.yaw_deg = 20;
    c.pitch_deg = -50;
    c.width = 320, c.height = 240;
    HeightmapPassSettings s = centres_only();
    s.skirt_quads = 0;  // the seam itself must be closed, not hidden by a skirt
    for (const int step : {1, 4}) {
        s.fixed_step = step;
        const Framebuffer fb = render(c, patches, s);
        const auto union_quad = screen_quad(c, kX0, kY0, kX0 + 1280, kY0 + 640, 100.0);
        for (const ScreenPoint& p : union_quad) ASSERT_TRUE(p.x > 0 && p.x < 320 && p.y > 0 && p.y < 240);
        const CoverageErrors e = check_coverage(fb, union_quad);
        EXPECT_GT(e.inside, 10'000);
        EXPECT_EQ(e.holes, 0) << "step " << step;
        EXPECT_EQ(e.spill, 0) << "step " << step;
    }
}

TEST(RenderHeightmapPass, SkirtsCloseTheStepBetweenPatchesOfDifferentHeights) {
    // The northern patch is 8 m higher; seen from the south, the step between them is open
    // without skirts and closed by the northern patch's skirt.
    const std::vector<OwnedPatch> patches = {flat_patch(kX0, kY0, 100.0f, pack_rgba(200, 0, 0)),
                                             flat_patch(kX0, kY0 + 640.0, 108.0f, pack_rgba(0, 0, 200))};
    Camera c;
    c.x = kX0 + 320.0, c.y = kY0 - 300.0, c.z = 420.0;
    c.pitch_deg = -30;
    c.width = 320, c.height = 240;
    const auto columns_with_gaps = [&](const Framebuffer& fb) {
        int gaps = 0;
        for (int x = 100; x < 220; ++x) {
            int first = -1, last = -1, drawn = 0;
            for (int y = 0; y < fb.height(); ++y) {
                if (fb.empty_at(x, y)) continue;
                if (first < 0) first = y;
                last = y;
                ++drawn;
            }
            gaps += first >= 0 && drawn != last - first + 1;
        }
        return gaps;
    };
    HeightmapPassSettings s = centres_only();
    EXPECT_EQ(columns_with_gaps(render(c, patches, s)), 0);
    s.skirt_quads = 0;
    EXPECT_EQ(columns_with_gaps(render(c, patches, s)), 120);  // the control: an open slit
}

TEST(RenderHeightmapPass, NanTexelLeavesAHole) {
    OwnedPatch patch = flat_patch(kX0, kY0, 100.0f, pack_rgba(100, 100, 100));
    patch.height(30, 20) = std::nanf("");  // covers x in [200, 210), y in [300, 310) m
    const Camera c = top_down(kX0 + 205.0, kY0 + 305.0, 400.0);
    HeightmapPassSettings s = centres_only();
    s.fixed_step = 1;
    const Framebuffer fb = render(c, {patch}, s);
    const auto hole = screen_quad(c, kX0 + 200, kY0 + 300, kX0 + 210, kY0 + 310, 100.0);
    const auto ring = screen_quad(c, kX0 + 180, kY0 + 280, kX0 + 230, kY0 + 330, 100.0);
    int empty_in_hole = 0, empty_in_ring = 0, hole_pixels = 0;
    for (int y = 0; y < 256; ++y) {
        for (int x = 0; x < 256; ++x) {
            const float cx = x + 0.5f, cy = y + 0.5f;
            if (inside_quad(hole, cx, cy, 0.01f)) {
                ++hole_pixels;
                empty_in_hole += fb.empty_at(x, y);
            } else if (!inside_quad(hole, cx, cy, -0.01f) && inside_quad(ring, cx, cy, 0.01f)) {
                empty_in_ring += fb.empty_at(x, y);
            }
        }
    }
    EXPECT_GT(hole_pixels, 30);
    EXPECT_EQ(empty_in_hole, hole_pixels);
    EXPECT_EQ(empty_in_ring, 0);
}

TEST(RenderHeightmapPass, PointsOnTheSurfaceWinButPointsBelowItDoNot) {
    const OwnedPatch patch = flat_patch(kX0, kY0, 100.0f, pack_rgba(200, 0, 0));
    const Camera c = top_down(kX0 + 320.0, kY0 + 320.0, 1100.0);
    // One point on the surface, one 5 m below it (beyond the 0.2% depth bias at 1 km).
    std::vector<PointAttr> points(2);
    points[0].dx = 0.5f, points[0].dy = 0.5f, points[0].dz = 0.0f, points[0].g = 255;
    points[1].dx = 100.5f, points[1].dy = 0.5f, points[1].dz = -5.0f, points[1].b = 255;
    const PointBatch batch{kX0 + 320.0, kY0 + 320.0, 100.0, points};
    const auto on = projected(c, kX0 + 320.5, kY0 + 320.5, 100.0);
    const auto below = projected(c, kX0 + 420.5, kY0 + 320.5, 95.0);
    ThreadPool pool(2);
    for (const bool points_first : {true, false}) {
        Framebuffer fb(c.width, c.height);
        const std::vector<HeightmapPatch> patches = {patch.view()};
        if (points_first) draw_points(fb, c, std::span(&batch, 1), {}, pool);
        draw_heightmaps(fb, c, patches, {}, pool);
        if (!points_first) draw_points(fb, c, std::span(&batch, 1), {}, pool);
        EXPECT_EQ(fragment_rgba(fb.at(static_cast<int>(on.x), static_cast<int>(on.y))), pack_rgba(0, 255, 0));
        const std::uint32_t hidden = fragment_rgba(fb.at(static_cast<int>(below.x), static_cast<int>(below.y)));
        EXPECT_GT(red(hidden), 100);
        EXPECT_EQ(blue(hidden), 0);
    }
}

TEST(RenderHeightmapPass, ElevationModeColoursByHeight) {
    OwnedPatch patch = flat_patch(kX0, kY0, 0.0f, pack_rgba(120, 120, 120));
    for (int row = 0; row < 64; ++row)
        for (int col = 0; col < 64; ++col) patch.height(row, col) = 100.0f + 2.0f * col;  // a plane rising east
    const Camera c = top_down(kX0 + 320.0, kY0 + 320.0, 1500.0);
    HeightmapPassSettings s = centres_only();
    const Framebuffer rgb = render(c, {patch}, s);
    s.colour.mode = ColourMode::Elevation;
    s.colour.z_min = 100;
    s.colour.z_max = 228;
    const Framebuffer elevation = render(c, {patch}, s);
    // The textured plane has one colour everywhere (one normal, one texture colour) ...
    EXPECT_EQ(fragment_rgba(rgb.at(90, 128)), fragment_rgba(rgb.at(166, 128)));
    // ... coloured by elevation, west and east differ, as the ramp does.
    const std::uint32_t west = fragment_rgba(elevation.at(90, 128)), east = fragment_rgba(elevation.at(166, 128));
    EXPECT_NE(west, east);
    EXPECT_GT(blue(west), red(west));   // low: the blue end of the ramp
    EXPECT_GT(red(east), blue(east));   // high: the warm end
}

TEST(RenderHeightmapPass, SlopesFacingTheSunAreBrighter) {
    OwnedPatch patch = flat_patch(kX0, kY0, 0.0f, pack_rgba(200, 200, 200));
    for (int row = 0; row < 64; ++row)
        for (int col = 0; col < 64; ++col) patch.height(row, col) = 100.0f + 4.0f * (32.0f - std::abs(col - 31.5f));
    const Camera c = top_down(kX0 + 320.0, kY0 + 320.0, 1500.0);
    const Framebuffer fb = render(c, {patch});
    // West half faces west (towards the north-west sun), east half faces away from it.
    EXPECT_GT(red(fragment_rgba(fb.at(100, 128))), red(fragment_rgba(fb.at(156, 128))) + 20);
}

TEST(RenderHeightmapPass, LevelOfDetailCoarsensWithDistance) {
    const OwnedPatch patch = flat_patch(kX0, kY0, 100.0f, 0);
    int previous = 0;
    for (const double altitude : {150.0, 600.0, 2000.0, 5000.0, 20000.0, 100000.0}) {
        const Camera c = top_down(kX0 + 320.0, kY0 + 320.0, 100.0 + altitude);
        const int step = lod_step(patch.view(), 100.0, 100.0, c, 3.0f);
        EXPECT_EQ(step & (step - 1), 0) << step;  // a power of two
        EXPECT_GE(step, previous);
        EXPECT_LE(step, 64);
        previous = step;
    }
    EXPECT_EQ(lod_step(patch.view(), 100.0, 100.0, top_down(kX0 + 320.0, kY0 + 320.0, 250.0), 3.0f), 1);
    EXPECT_EQ(previous, 64);
}

TEST(RenderHeightmapPass, PatchBehindTheCameraDrawsNothing) {
    const OwnedPatch patch = flat_patch(kX0, kY0, 100.0f, pack_rgba(255, 255, 255));
    Camera c;
    c.x = kX0 + 320.0, c.y = kY0 + 700.0, c.z = 150.0;  // north of the patch, looking north
    c.width = c.height = 64;
    const Framebuffer fb = render(c, {patch});
    for (int y = 0; y < 64; ++y)
        for (int x = 0; x < 64; ++x) ASSERT_TRUE(fb.empty_at(x, y));
}

TEST(RenderHeightmapPass, ATintMixesTheMarkedTexelsOrTheWholePatchTowardsItsColour) {
    // A level grey patch whose western half is marked (alpha below 255): the viewer's overview
    // texels where a ground filter wants bare earth.
    OwnedPatch patch = flat_patch(kX0, kY0, 0.0f, pack_rgba(100, 100, 100));
    for (int row = 0; row < 64; ++row)
        for (int col = 0; col < 32; ++col) patch.colours[static_cast<std::size_t>(row) * 64 + col] = 0x80646464u;
    const Camera c = top_down(kX0 + 320.0, kY0 + 320.0, 1500.0);
    const HeightmapPassSettings s = centres_only();
    const auto west = [&](const Framebuffer& fb) { return fragment_rgba(fb.at(95, 128)); };
    const auto east = [&](const Framebuffer& fb) { return fragment_rgba(fb.at(160, 128)); };
    const Framebuffer none = render(c, {patch}, s);
    EXPECT_EQ(west(none), east(none)) << "untinted, the alpha is not drawn";
    EXPECT_NEAR(red(east(none)), 100, 2);
    patch.tint = PatchTint::Marked;
    const Framebuffer marked = render(c, {patch}, s);
    EXPECT_EQ(east(marked), east(none)) << "unmarked texels keep their colour";
    const float mix = s.tint_strength;  // level ground: the texture's own colour, mixed
    EXPECT_NEAR(red(west(marked)), 100 + (s.tint_rgb[0] - 100) * mix, 3);
    EXPECT_NEAR(green(west(marked)), 100 + (s.tint_rgb[1] - 100) * mix, 3);
    patch.tint = PatchTint::All;
    const Framebuffer all = render(c, {patch}, s);
    EXPECT_EQ(east(all), west(marked));
    EXPECT_EQ(west(all), west(marked));
    HeightmapPassSettings elevation = s;  // the ramp's colours are tinted too
    elevation.colour.mode = ColourMode::Elevation;
    const Framebuffer ramp = render(c, {patch}, elevation);
    patch.tint = PatchTint::None;
    const Framebuffer plain_ramp = render(c, {patch}, elevation);
    EXPECT_NE(west(ramp), west(plain_ramp));
}

TEST(RenderHeightmapPass, RejectsMalformedPatches) {
    const Camera c = top_down(kX0, kY0, 1000.0, 32);
    Framebuffer fb(32, 32);
    ThreadPool pool(1);
    OwnedPatch patch = flat_patch(kX0, kY0, 1.0f, 0);
    patch.heights.pop_back();
    std::vector<HeightmapPatch> patches = {patch.view()};
    EXPECT_THROW(draw_heightmaps(fb, c, patches, {}, pool), Error);
    patch = flat_patch(kX0, kY0, 1.0f, 0);
    patch.colours.resize(10);
    patches = {patch.view()};
    EXPECT_THROW(draw_heightmaps(fb, c, patches, {}, pool), Error);
    patch.colours.clear();  // untextured is fine
    patches = {patch.view()};
    EXPECT_NO_THROW(draw_heightmaps(fb, c, patches, {}, pool));
    patch.tint = PatchTint::Marked;  // but its marks are in the colours
    patches = {patch.view()};
    EXPECT_THROW(draw_heightmaps(fb, c, patches, {}, pool), Error);
    patch.tint = PatchTint::None;
    patch.texel_m = 0;
    patches = {patch.view()};
    EXPECT_THROW(draw_heightmaps(fb, c, patches, {}, pool), Error);
}

}  // namespace
}  // namespace lidarscout::render
