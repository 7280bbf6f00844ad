// viewer/app/overlay: a footprint seen from straight above is the closed outline of its projected corners' pixels
// (every pixel of its four sides, none inside or outside), a box reaching past the image is clipped to it, and
// one out of view draws nothing.
#include "viewer/app/overlay.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <vector>

namespace lidarscout::viewer::app {
namespace {

constexpr std::uint32_t kInk = 0xff00ffffu;

// 200 x 100 pixels, 1,000 m above the origin looking straight down, north up.
render::Camera top_down() {
    render::Camera c;
    c.z = 1000, c.pitch_deg = -90, c.yaw_deg = 0, c.width = 200, c.height = 100;
    return c;
}

render::RgbaImage blank(const render::Camera& c) {
    render::RgbaImage image;
    image.width = c.width, image.height = c.height;
    image.pixels.assign(static_cast<std::size_t>(c.width) * c.height, 0u);
    return image;
}

dataset::Bounds box(double x0, double y0, double x1, double y1) {
    dataset::Bounds b;
    b.min_x = x0, b.min_y = y0, b.min_z = 0, b.max_x = x1, b.max_y = y1, b.max_z = 10;
    return b;
}

// The pixels (x, y) where `image` holds ink.
std::vector<std::pair<int, int>> inked(const render::RgbaImage& image) {
    std::vector<std::pair<int, int>> out;
    for (int y = 0; y < image.height; ++y) {
        for (int x = 0; x < image.width; ++x) {
            if (image.pixels[static_cast<std::size_t>(y) * image.width + x] == kInk) out.emplace_back(x, y);
        }
    }
    return out;
}

// The border of the pixel rectangle [x0, x1] x [y0, y1], in inked()'s order.
std::vector<std::pair<int, int>> border(int x0, int y0, int x1, int y1) {
    std::vector<std::pair<int, int>> out;
    for (int y = y0; y <= y1; ++y) {
        for (int x = x0; x <= x1; ++x) {
            if (y == y0 || y == y1 || x == x0 || x == x1) out.emplace_back(x, y);
        }
    }
    return out;
}

// The pixel a world position projects to (rounded as pixels are drawn).
std::pair<int, int> pixel_of(const render::Camera& c, double x, double y) {
    const auto p = c.project(x, y, 0);
    return {static_cast<int>(std::lround(p->x)), static_cast<int>(std::lround(p->y))};
}

TEST(Footprints, SeenFromAboveAreTheOutlineOfTheirCorners) {
    const render::Camera c = top_down();
    auto image = blank(c);
    const dataset::Bounds b = box(-200, -100, 300, 150);
    draw_footprints(image, c, std::span(&b, 1), kInk);
    const auto [x0, y1] = pixel_of(c, -200, -100);  // (south-west: lower left)
    const auto [x1, y0] = pixel_of(c, 300, 150);
    ASSERT_LT(x0 + 10, x1);
    ASSERT_LT(y0 + 10, y1);
    EXPECT_EQ(inked(image), border(x0, y0, x1, y1));
}

TEST(Footprints, AreClippedToTheImageAndNotDrawnOutOfView) {
    const render::Camera c = top_down();
    auto image = blank(c);
    const dataset::Bounds wide = box(-200, -100, 5000, 150);  // its east side far beyond the image's right edge
    draw_footprints(image, c, std::span(&wide, 1), kInk);
    const auto [x0, y1] = pixel_of(c, -200, -100);
    const auto [x_far, y0] = pixel_of(c, 5000, 150);
    ASSERT_GT(x_far, c.width);
    std::vector<std::pair<int, int>> expected;
    for (const auto& p : border(x0, y0, c.width - 1, y1)) {
        if (p.first < c.width - 1 || p.second == y0 || p.second == y1) expected.push_back(p);  // (no east side)
    }
    EXPECT_EQ(inked(image), expected);

    auto untouched = blank(c);
    const dataset::Bounds away = box(20000, 20000, 20500, 20500);
    draw_footprints(untouched, c, std::span(&away, 1), kInk);
    EXPECT_TRUE(inked(untouched).empty());
}

}  // namespace
}  // namespace lidarscout::viewer::app
