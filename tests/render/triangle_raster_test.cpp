// Triangle rasterizer: a mesh covers every pixel centre inside it exactly once (top-left
// rule, including centres exactly on shared edges), perspective-correct depth, shading and
// clipping.
#include <gtest/gtest.h>

#include <random>
#include <vector>

#include "render/triangle_raster.hpp"

namespace lidarscout::render {
namespace {

RasterVertex vertex(float x, float y, float depth = 10.0f, float grey = 200.0f) {
    return RasterVertex{x, y, depth, grey, grey, grey};
}

// How many of the triangles cover each pixel.
std::vector<int> coverage(int w, int h, const std::vector<std::array<RasterVertex, 3>>& triangles) {
    std::vector<int> count(static_cast<std::size_t>(w) * h, 0);
    for (const auto& t : triangles) {
        Framebuffer fb(w, h);
        draw_triangle(fb, t[0], t[1], t[2], 1.0f, 1.0f);
        for (int y = 0; y < h; ++y)
            for (int x = 0; x < w; ++x) count[static_cast<std::size_t>(y) * w + x] += !fb.empty_at(x, y);
    }
    return count;
}

// A w x h grid of quads over [x0, x0 + n * cell]^2, vertices jittered (or not), two triangles
// per quad split along alternating diagonals.
std::vector<std::array<RasterVertex, 3>> grid_mesh(int n, float x0, float cell, float jitter, unsigned seed) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<float> d(-jitter, jitter);
    std::vector<RasterVertex> v;
    for (int j = 0; j <= n; ++j) {
        for (int i = 0; i <= n; ++i) {
            const bool inner = i > 0 && j > 0 && i < n && j < n;
            v.push_back(vertex(x0 + i * cell + (inner ? d(rng) : 0.0f), x0 + j * cell + (inner ? d(rng) : 0.0f)));
        }
    }
    std::vector<std::array<RasterVertex, 3>> triangles;
    const auto at = [&](int i, int j) { return v[static_cast<std::size_t>(j) * (n + 1) + i]; };
    for (int j = 0; j < n; ++j) {
        for (int i = 0; i < n; ++i) {
            if ((i + j) % 2) {
                triangles.push_back({at(i, j), at(i + 1, j), at(i + 1, j + 1)});
                triangles.push_back({at(i, j), at(i + 1, j + 1), at(i, j + 1)});
            } else {
                triangles.push_back({at(i, j), at(i + 1, j), at(i, j + 1)});
                triangles.push_back({at(i + 1, j + 1), at(i, j + 1), at(i + 1, j)});  // other winding
            }
        }
    }
    return triangles;
}

TEST(RenderTriangle, MeshCoversEveryPixelCentreExactlyOnce) {
    // Integer-pixel cells put many pixel centres exactly on edges and vertices; the jittered
    // mesh has arbitrary slopes.
    for (const float jitter : {0.0f, 1.7f}) {
        const auto count = coverage(48, 48, grid_mesh(8, 4.0f, 5.0f, jitter, 11));
        int inside = 0;
        for (int y = 0; y < 48; ++y) {
            for (int x = 0; x < 48; ++x) {
                const float cx = x + 0.5f, cy = y + 0.5f;
                const bool in_mesh = cx > 4.0f && cx < 44.0f && cy > 4.0f && cy < 44.0f;
                EXPECT_EQ(count[y * 48 + x], in_mesh ? 1 : 0) << "jitter " << jitter << " pixel " << x << "," << y;
                inside += in_mesh;
            }
        }
        EXPECT_EQ(inside, 40 * 40);
    }
}

TEST(RenderTriangle, SharedEdgeThroughPixelCentresIsOwnedOnce) {
    // Two triangles split a square along a diagonal passing exactly through pixel centres.
    const auto a = vertex(0.5f, 0.5f), b = vertex(8.5f, 0.5f), c = vertex(8.5f, 8.5f), d = vertex(0.5f, 8.5f);
    const auto count = coverage(10, 10, {{a, b, c}, {a, c, d}});
    for (int i = 1; i < 8; ++i) EXPECT_EQ(count[i * 10 + i], 1) << i;  // on the diagonal
    int total = 0;
    for (const int n : count) {
        EXPECT_LE(n, 1);
        total += n;
    }
    // Centres strictly inside the square, (1..7)^2, plus its top row and left column but not
    // the bottom-left and top-right corners: 49 + 8 + 8 - 1.
    EXPECT_EQ(total, 64);
    EXPECT_EQ(count[0], 1);
    EXPECT_EQ(count[8 * 10 + 8], 0);
}

TEST(RenderTriangle, DepthIsPerspectiveCorrect) {
    Framebuffer fb(16, 4);
    // Depth 1 on the left edge, 3 on the right: halfway on screen the depth is the harmonic
    // mean 1.5, not 2.
    draw_triangle(fb, vertex(0.0f, -10.0f, 1.0f), vertex(16.0f, 2.0f, 3.0f), vertex(0.0f, 14.0f, 1.0f), 1.0f, 1.0f);
    // Pixel 7 has its centre at x = 7.5: the weight of the right vertex is 7.5 / 16.
    const float t = 7.5f / 16.0f;
    EXPECT_NEAR(fragment_depth(fb.at(7, 2)), 1.0f / ((1 - t) / 1.0f + t / 3.0f), 1e-4);
    // The depth scale (bias) multiplies the depth.
    Framebuffer biased(16, 4);
    draw_triangle(biased, vertex(0.0f, -10.0f, 1.0f), vertex(16.0f, 2.0f, 3.0f), vertex(0.0f, 14.0f, 1.0f), 1.0f,
                  1.01f);
    EXPECT_NEAR(fragment_depth(biased.at(7, 2)), 1.01f * fragment_depth(fb.at(7, 2)), 1e-4);
}

TEST(RenderTriangle, ColoursAreInterpolatedAndShaded) {
    Framebuffer fb(16, 16);
    RasterVertex a{0.0f, 0.0f, 5.0f, 0.0f, 100.0f, 200.0f}, b{32.0f, 0.0f, 5.0f, 0.0f, 100.0f, 200.0f},
        c{0.0f, 32.0f, 5.0f, 200.0f, 100.0f, 200.0f};
    draw_triangle(fb, a, b, c, 0.5f, 1.0f);
    const std::uint32_t top = fragment_rgba(fb.at(4, 0)), lower = fragment_rgba(fb.at(4, 12));
    EXPECT_EQ(green(top), 50);  // 100 * shade
    EXPECT_EQ(blue(top), 100);
    EXPECT_NEAR(red(top), 0.5 * 200 * 0.5 / 32, 1);
    EXPECT_NEAR(red(lower), 0.5 * 200 * 12.5 / 32, 1);  // red grows with y
    EXPECT_EQ(alpha(top), 255);
}

TEST(RenderTriangle, DegenerateAndFarOutsideTrianglesDrawNothing) {
    Framebuffer fb(16, 16);
    draw_triangle(fb, vertex(1, 1), vertex(5, 5), vertex(9, 9), 1.0f, 1.0f);                // zero area
    draw_triangle(fb, vertex(-40, -40), vertex(-20, -40), vertex(-30, -20), 1.0f, 1.0f);    // off screen
    draw_triangle(fb, vertex(2, 2), vertex(3e6f, 2), vertex(2, 12), 1.0f, 1.0f);            // beyond the guard band
    for (int y = 0; y < 16; ++y)
        for (int x = 0; x < 16; ++x) EXPECT_TRUE(fb.empty_at(x, y));
    // A triangle larger than the screen is clipped to it.
    draw_triangle(fb, vertex(-100, -100), vertex(300, -100), vertex(-100, 300), 1.0f, 1.0f);
    for (int y = 0; y < 16; ++y)
        for (int x = 0; x < 16; ++x) EXPECT_FALSE(fb.empty_at(x, y));
}

}  // namespace
}  // namespace lidarscout::render
