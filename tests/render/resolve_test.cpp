// Resolve: background and colours, eye-dome lighting at depth edges (and not on a plane), and
// PNG output read back.
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <string>

#include "core/error.hpp"
#include "render/png_writer.hpp"
#include "render/resolve.hpp"
#include "png_test_util.hpp"


namespace lidarscout::render {
namespace {

// A 24 x 24 plane at depth 20 with a 8 x 8 square at depth 10 in the middle (8..15).
Framebuffer step_scene(std::uint32_t colour) {
    Framebuffer fb(24, 24);
    for (int y = 0; y < 24; ++y) {
        for (int x = 0; x < 24; ++x) {
            const bool square = x >= 8 && x < 16 && y >= 8 && y < 16;
            fb.write(x, y, square ? 10.0f : 20.0f, colour);
        }
    }
    return fb;
}

TEST(RenderResolve, BackgroundWhereEmptyColourWhereDrawn) {
    Framebuffer fb(5, 4);
    fb.write(2, 1, 3.0f, pack_rgba(1, 2, 3));
    ResolveSettings s;
    s.background = pack_rgba(9, 8, 7, 255);
    ThreadPool pool(2);
    const RgbaImage image = resolve(fb, s, pool);
    ASSERT_EQ(image.width, 5);
    ASSERT_EQ(image.height, 4);
    for (int y = 0; y < 4; ++y)
        for (int x = 0; x < 5; ++x) EXPECT_EQ(image.at(x, y), (x == 2 && y == 1) ? pack_rgba(1, 2, 3) : s.background);
}

TEST(RenderResolve, EyeDomeLightingDarkensDepthEdgesOnly) {
    const std::uint32_t grey = pack_rgba(200, 200, 200);
    const Framebuffer fb = step_scene(grey);
    ThreadPool pool(2);
    ResolveSettings s;
    s.edl_strength = 1.0f;
    const RgbaImage image = resolve(fb, s, pool);
    // Far pixels next to the near square are darkened; the near square and far pixels away
    // from the edge keep their colour.
    EXPECT_LT(red(image.at(7, 12)), 100);
    EXPECT_LT(red(image.at(12, 16)), 100);
    EXPECT_EQ(image.at(8, 12), grey);
    EXPECT_EQ(image.at(12, 12), grey);
    EXPECT_EQ(image.at(3, 3), grey);
    EXPECT_EQ(image.at(5, 12), grey);
    // A larger radius reaches farther from the edge.
    s.edl_radius_px = 3;
    EXPECT_LT(red(resolve(fb, s, pool).at(5, 12)), 100);
    // Off: the colours as drawn.
    s.edl_strength = 0.0f;
    EXPECT_EQ(resolve(fb, s, pool).at(7, 12), grey);
}

TEST(RenderResolve, EyeDomeLightingLeavesAPlaneAndSilhouettesAlone) {
    // A plane facing the camera has one depth everywhere; the empty border is background.
    Framebuffer fb(16, 16);
    for (int y = 2; y < 14; ++y)
        for (int x = 2; x < 14; ++x) fb.write(x, y, 42.0f, pack_rgba(50, 150, 250));
    ThreadPool pool(1);
    ResolveSettings s;
    s.edl_strength = 2.0f;
    const RgbaImage image = resolve(fb, s, pool);
    for (int y = 2; y < 14; ++y)
        for (int x = 2; x < 14; ++x) EXPECT_EQ(image.at(x, y), pack_rgba(50, 150, 250)) << x << "," << y;
}

TEST(RenderResolve, RejectsBadSettings) {
    const Framebuffer fb(4, 4);
    ThreadPool pool(1);
    ResolveSettings s;
    s.edl_strength = -1.0f;
    EXPECT_THROW(resolve(fb, s, pool), Error);
    s = {};
    s.edl_radius_px = 0;
    EXPECT_THROW(resolve(fb, s, pool), Error);
}

TEST(RenderPng, WrittenImageReadsBack) {
    const Framebuffer fb = step_scene(pack_rgba(10, 200, 30));
    ThreadPool pool(1);
    ResolveSettings s;
    s.edl_strength = 1.0f;
    const RgbaImage image = resolve(fb, s, pool);
    const auto path =
        std::filesystem::temp_directory_path() / ("lidarscout_render_" + std::to_string(::getpid()) + ".png");
    write_png(path.string(), image);
    const test::Png png = test::read_png(path);
    std::filesystem::remove(path);
    ASSERT_TRUE(png.ok());
    EXPECT_EQ(png.width, 24);
    EXPECT_EQ(png.height, 24);
    for (std::size_t i = 0; i < png.pixels.size(); ++i) ASSERT_EQ(png.pixels[i], image.pixels[i]) << i;
}

TEST(RenderPng, UnwritablePathIsAnError) {
    RgbaImage image{2, 2, std::vector<std::uint32_t>(4, pack_rgba(1, 2, 3))};
    EXPECT_THROW(write_png("/nonexistent-dir/x/y.png", image), Error);
    image.pixels.pop_back();
    EXPECT_THROW(write_png("/tmp/never-written.png", image), Error);
}

}  // namespace
}  // namespace lidarscout::render
