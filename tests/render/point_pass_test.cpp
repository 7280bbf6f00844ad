// Point pass: points land in the expected pixel with their colour, point sizes cover N x N,
// adaptive sizes follow the batch's spacing on screen (and points on a grid meet),
// the nearest point wins, clipping, colour modes, filters, and the result does not depend on threads.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <random>
#include <vector>

#include "core/error.hpp"
#include "render/point_pass.hpp"

namespace lidarscout::render {
namespace {

// 64 x 48, looking north, level, at survey-sized coordinates. Focal length 41.57 px.
Camera test_camera() {
    Camera c;
    c.x = 654'321.0;
    c.y = 5'432'100.0;
    c.z = 250.0;
    c.width = 64;
    c.height = 48;
    return c;
}

// Metres that move a point `px` pixels at `depth` metres.
double metres(double px, double depth) { return px * depth / test_camera().focal_px(); }

PointAttr attr(double dx, double dy, double dz, std::uint8_t r, std::uint8_t g, std::uint8_t b) {
    PointAttr p;
    p.dx = static_cast<float>(dx);
    p.dy = static_cast<float>(dy);
    p.dz = static_cast<float>(dz);
    p.r = r, p.g = g, p.b = b;
    return p;
}

// A batch whose origin is a few hundred metres from the camera.
PointBatch batch_at(const Camera& c, const std::vector<PointAttr>& points) {
    return PointBatch{c.x - 30.5, c.y + 80.25, c.z - 12.0, points};
}

// The point `right_px` right of and `down_px` below the image centre at `depth`, relative to
// batch_at's origin.
PointAttr on_screen(double right_px, double down_px, double depth, std::uint8_t r, std::uint8_t g, std::uint8_t b) {
    return attr(30.5 + metres(right_px, depth), depth - 80.25, 12.0 - metres(down_px, depth), r, g, b);
}

// `n` points of random colours scattered 20-200 m ahead of the camera, relative to batch_at's origin.
std::vector<PointAttr> random_points(std::size_t n, unsigned seed) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<float> lateral(-60.0f, 60.0f), depth(20.0f, 200.0f);
    std::vector<PointAttr> points(n);
    for (PointAttr& p : points) {
        p = attr(30.5 + lateral(rng), depth(rng) - 80.25, 12.0 + 0.5 * lateral(rng), static_cast<std::uint8_t>(rng()),
                 static_cast<std::uint8_t>(rng()), static_cast<std::uint8_t>(rng()));
    }
    return points;
}

int covered(const Framebuffer& fb) {
    int n = 0;
    for (int y = 0; y < fb.height(); ++y)
        for (int x = 0; x < fb.width(); ++x) n += !fb.empty_at(x, y);
    return n;
}

TEST(RenderPointPass, SinglePointLandsInItsPixelWithItsColour) {
    const Camera c = test_camera();
    const std::vector<PointAttr> points = {on_screen(0.25, 0.25, 100.0, 200, 100, 50),
                                           on_screen(4.5, -3.5, 300.0, 10, 20, 30)};
    const PointBatch batch = batch_at(c, points);
    Framebuffer fb(c.width, c.height);
    ThreadPool pool(2);
    draw_points(fb, c, std::span(&batch, 1), {}, pool);
    EXPECT_EQ(covered(fb), 2);
    ASSERT_FALSE(fb.empty_at(32, 24));
    EXPECT_EQ(fragment_rgba(fb.at(32, 24)), pack_rgba(200, 100, 50));
    EXPECT_NEAR(fragment_depth(fb.at(32, 24)), 100.0f, 1e-3);
    ASSERT_FALSE(fb.empty_at(36, 20));
    EXPECT_EQ(fragment_rgba(fb.at(36, 20)), pack_rgba(10, 20, 30));
    EXPECT_NEAR(fragment_depth(fb.at(36, 20)), 300.0f, 1e-3);
}

TEST(RenderPointPass, AFilterDrawsOnlyWhatItKeeps) {
    const Camera c = test_camera();
    std::vector<PointAttr> points = {on_screen(0.25, 0.25, 100.0, 200, 100, 50),   // class 2, last, 10
                                     on_screen(4.5, -3.5, 300.0, 10, 20, 30),      // class 5, first, 900
                                     on_screen(-6.5, 5.5, 200.0, 1, 2, 3)};        // class 5, unknown returns, 400
    points[0].classification = 2, points[0].returns = returns::kLast, points[0].intensity = 10;
    points[1].classification = 5, points[1].returns = returns::kFirst, points[1].intensity = 900;
    points[2].classification = 5, points[2].returns = 0, points[2].intensity = 400;
    const PointBatch batch = batch_at(c, points);
    ThreadPool pool(2);
    const auto drawn = [&](const char* classes, const char* kinds, const char* intensity) {
        Framebuffer fb(c.width, c.height);
        PointPassSettings s;
        s.filter = PointFilter::parse(classes, kinds, intensity);
        s.point_size = 1 + (classes[0] == '5');  // squares as well as single pixels
        draw_points(fb, c, std::span(&batch, 1), s, pool);
        const int area = s.point_size * s.point_size;
        return std::array<bool, 4>{!fb.empty_at(32, 24), !fb.empty_at(36, 20), !fb.empty_at(25, 29),
                                   covered(fb) % area == 0};
    };
    EXPECT_EQ(drawn("", "", ""), (std::array<bool, 4>{true, true, true, true}));
    EXPECT_EQ(drawn("2", "", ""), (std::array<bool, 4>{true, false, false, true}));
    EXPECT_EQ(drawn("5", "", ""), (std::array<bool, 4>{false, true, true, true}));
    EXPECT_EQ(drawn("", "first", ""), (std::array<bool, 4>{false, true, true, true}));  // unknown passes
    EXPECT_EQ(drawn("", "", "100-500"), (std::array<bool, 4>{false, false, true, true}));
}

TEST(RenderPointPass, PointSizeCoversASquare) {
    const Camera c = test_camera();
    const std::vector<PointAttr> points = {on_screen(0.5, 0.5, 100.0, 255, 0, 0)};
    const PointBatch batch = batch_at(c, points);
    ThreadPool pool(1);
    for (const int size : {3, 4}) {
        Framebuffer fb(c.width, c.height);
        PointPassSettings s;
        s.point_size = size;
        draw_points(fb, c, std::span(&batch, 1), s, pool);
        EXPECT_EQ(covered(fb), size * size) << size;
        const int left = 32 - (size - 1) / 2, top = 24 - (size - 1) / 2;
        for (int y = top; y < top + size; ++y)
            for (int x = left; x < left + size; ++x) EXPECT_FALSE(fb.empty_at(x, y)) << size << " " << x << "," << y;
    }
    // A large point at the image corner is clipped, not wrapped or dropped.
    Framebuffer fb(c.width, c.height);
    const std::vector<PointAttr> corner = {on_screen(-31.5, -23.5, 100.0, 255, 0, 0)};
    const PointBatch corner_batch = batch_at(c, corner);
    PointPassSettings s;
    s.point_size = 5;
    draw_points(fb, c, std::span(&corner_batch, 1), s, pool);
    EXPECT_EQ(covered(fb), 9);
    EXPECT_FALSE(fb.empty_at(2, 2));
    EXPECT_TRUE(fb.empty_at(3, 3));
}

TEST(RenderPointPass, AdaptiveSizeIsTheSpacingOnScreenWithinItsBounds) {
    const Camera c = test_camera();
    ThreadPool pool(1);
    PointPassSettings s;
    s.adaptive_size = true;
    // 3.4 px at 100 m: squares of 4; 0.85 px at 400 m: single pixels; 34 px at 10 m: the largest.
    const std::pair<double, int> depths[] = {{100.0, 4}, {400.0, 1}, {10.0, kMaxAdaptivePointSize}};
    for (const auto& [depth, side] : depths) {
        const std::vector<PointAttr> points = {on_screen(0.5, 0.5, depth, 255, 0, 0)};
        PointBatch batch = batch_at(c, points);
        batch.spacing_m = static_cast<float>(metres(3.4, 100.0));
        Framebuffer fb(c.width, c.height);
        draw_points(fb, c, std::span(&batch, 1), s, pool);
        EXPECT_EQ(covered(fb), side * side) << depth;
        PointPassSettings fixed;  // the same batch without the adaptive size: one pixel
        Framebuffer one(c.width, c.height);
        draw_points(one, c, std::span(&batch, 1), fixed, pool);
        EXPECT_EQ(covered(one), 1) << depth;
    }
}

TEST(RenderPointPass, AdaptivePointsOnAGridMeet) {
    const Camera c = test_camera();
    std::vector<PointAttr> grid;  // 3.4 px apart at 100 m, from -13.6 to +13.6 px
    for (int i = -4; i <= 4; ++i) {
        for (int j = -4; j <= 4; ++j) grid.push_back(on_screen(3.4 * i + 0.5, 3.4 * j + 0.5, 100.0, 0, 255, 0));
    }
    PointBatch batch = batch_at(c, grid);
    batch.spacing_m = static_cast<float>(metres(3.4, 100.0));
    ThreadPool pool(2);
    const auto holes_inside = [&](bool adaptive) {
        PointPassSettings s;
        s.adaptive_size = adaptive;
        Framebuffer fb(c.width, c.height);
        draw_points(fb, c, std::span(&batch, 1), s, pool);
        int holes = 0;
        for (int y = 24 - 12; y <= 24 + 12; ++y)
            for (int x = 32 - 12; x <= 32 + 12; ++x) holes += fb.empty_at(x, y);
        return holes;
    };
    EXPECT_EQ(holes_inside(true), 0);
    EXPECT_GT(holes_inside(false), 500);  // single pixels leave most of the surface between them
}

TEST(RenderPointPass, NearestOfOverlappingPointsWinsInAnyOrder) {
    const Camera c = test_camera();
    const PointAttr near = on_screen(2.5, 2.5, 50.0, 0, 255, 0);
    const PointAttr far = on_screen(2.5, 2.5, 60.0, 255, 0, 0);
    ThreadPool pool(2);
    for (const bool near_first : {true, false}) {
        // In the same batch and in two batches with different origins.
        const std::vector<PointAttr> both = near_first ? std::vector{near, far} : std::vector{far, near};
        PointAttr far_shifted = far;
        far_shifted.dx -= 1000.0f;
        const std::vector<PointAttr> only_near = {near}, only_far = {far_shifted};
        const std::vector<PointBatch> one = {batch_at(c, both)};
        PointBatch near_batch = batch_at(c, only_near), far_batch = batch_at(c, only_far);
        far_batch.origin_x += 1000.0;
        const std::vector<PointBatch> two = near_first ? std::vector{near_batch, far_batch}
                                                       : std::vector{far_batch, near_batch};
        for (const auto* batches : {&one, &two}) {
            Framebuffer fb(c.width, c.height);
            draw_points(fb, c, *batches, {}, pool);
            EXPECT_EQ(covered(fb), 1);
            EXPECT_EQ(fragment_rgba(fb.at(34, 26)), pack_rgba(0, 255, 0)) << near_first;
        }
    }
}

TEST(RenderPointPass, PointsBehindNearFarOrOffScreenAreNotDrawn) {
    Camera c = test_camera();
    c.near_m = 1.0;
    c.far_m = 500.0;
    const std::vector<PointAttr> points = {
        attr(30.5, -80.25 - 20.0, 12.0, 1, 1, 1),           // behind the camera
        attr(30.5, -80.25 + 0.5, 12.0, 2, 2, 2),            // nearer than near
        attr(30.5, -80.25 + 600.0, 12.0, 3, 3, 3),          // beyond far
        on_screen(40.0, 0.0, 100.0, 4, 4, 4),               // right of the image
        on_screen(0.0, -30.0, 100.0, 5, 5, 5),              // above the image
        on_screen(0.5, 0.5, 499.0, 6, 6, 6),                // just inside
    };
    const PointBatch batch = batch_at(c, points);
    Framebuffer fb(c.width, c.height);
    ThreadPool pool(1);
    draw_points(fb, c, std::span(&batch, 1), {}, pool);
    EXPECT_EQ(covered(fb), 1);
    EXPECT_EQ(fragment_rgba(fb.at(32, 24)), pack_rgba(6, 6, 6));
}

TEST(RenderPointPass, ColourModesUseTheAttributes) {
    const Camera c = test_camera();
    std::vector<PointAttr> points = {on_screen(0.5, 0.5, 100.0, 1, 2, 3)};
    points[0].classification = 6;
    points[0].intensity = 65535;
    const PointBatch batch = batch_at(c, points);
    ThreadPool pool(1);
    const double z = batch.origin_z + points[0].dz;
    const auto colour_in = [&](ColourMode mode) {
        Framebuffer fb(c.width, c.height);
        PointPassSettings s;
        s.colour.mode = mode;
        s.colour.z_min = z - 512.5;  // 1 ramp entry per metre; the point in the middle of entry 512
        s.colour.z_max = z + 511.5;
        draw_points(fb, c, std::span(&batch, 1), s, pool);
        return fragment_rgba(fb.at(32, 24));
    };
    EXPECT_EQ(colour_in(ColourMode::Rgb), pack_rgba(1, 2, 3));
    EXPECT_EQ(colour_in(ColourMode::Classification), classification_colour(6));
    EXPECT_EQ(colour_in(ColourMode::Intensity), pack_rgba(255, 255, 255));
    const std::uint32_t elevation = colour_in(ColourMode::Elevation);
    EXPECT_EQ(elevation, elevation_ramp(512.5f / Palette::kRampSize));
}

TEST(RenderPointPass, ResultDoesNotDependOnThreadsOrChunks) {
    const Camera c = test_camera();
    const std::vector<PointAttr> points = random_points(200'000, 7);
    const PointBatch batch = batch_at(c, points);
    Framebuffer one(c.width, c.height), many(c.width, c.height);
    ThreadPool single(1), pool(4);
    PointPassSettings s;
    draw_points(one, c, std::span(&batch, 1), s, single);
    s.chunk_points = 1000;
    draw_points(many, c, std::span(&batch, 1), s, pool);
    EXPECT_GT(covered(one), c.width * c.height / 2);
    EXPECT_TRUE(std::equal(one.data(), one.data() + c.width * c.height, many.data()));
}

// Work items span batches (a country's view is 600,000 cells of a few points): the same points in batches of
// uneven sizes, empty ones among them, give the one batch's picture whatever the points per item.
TEST(RenderPointPass, ItemsAcrossManyBatchesDrawEveryPointOnce) {
    const Camera c = test_camera();
    const std::vector<PointAttr> points = random_points(20'000, 11);
    const PointBatch whole = batch_at(c, points);
    std::vector<PointBatch> pieces;
    const std::size_t sizes[] = {0, 1, 3, 17, 250, 2, 0, 999};
    for (std::size_t at = 0, k = 0; at < points.size(); ++k) {
        const std::size_t n = std::min(sizes[k % std::size(sizes)], points.size() - at);
        pieces.push_back(batch_at(c, {}));
        pieces.back().points = std::span(points).subspan(at, n);
        at += n;
    }
    ThreadPool single(1), pool(3);
    PointPassSettings s;
    Framebuffer one(c.width, c.height);
    draw_points(one, c, std::span(&whole, 1), s, single);
    ASSERT_GT(covered(one), c.width * c.height / 2);
    for (const std::size_t per_item : {1, 7, 1000, 50'000}) {
        s.chunk_points = per_item;
        Framebuffer split(c.width, c.height);
        draw_points(split, c, pieces, s, pool);
        EXPECT_TRUE(std::equal(one.data(), one.data() + c.width * c.height, split.data())) << per_item;
    }
}

TEST(RenderPointPass, RejectsBadSettings) {
    const Camera c = test_camera();
    Framebuffer fb(c.width, c.height), other(32, 32);
    ThreadPool pool(1);
    PointPassSettings s;
    EXPECT_THROW(draw_points(other, c, {}, s, pool), Error);
    s.point_size = 0;
    EXPECT_THROW(draw_points(fb, c, {}, s, pool), Error);
    s.point_size = 65;
    EXPECT_THROW(draw_points(fb, c, {}, s, pool), Error);
}

}  // namespace
}  // namespace lidarscout::render
