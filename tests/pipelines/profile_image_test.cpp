// profile_image: the PNG a user gets is at true scale (a unit of height as many pixels as a unit of
// distance, in metres when the units differ; --exaggeration multiplies it), has tick values and axis
// titles in its margins, and draws ground over the other classes wherever they share a pixel; the
// viewer's panel keeps its fixed size.
#include <gtest/gtest.h>

#include <cmath>

#include "core/error.hpp"
#include "dataset/dataset.hpp"
#include "las/crs.hpp"
#include "pipelines/profile_image.hpp"
#include "render/colour_modes.hpp"
#include "render/framebuffer.hpp"

namespace lidarscout::pipelines {
namespace {

const std::uint32_t kText = render::pack_rgba(215, 217, 225);

ProfilePoint point(double distance, double z, std::uint8_t classification) {
    ProfilePoint p;
    p.distance = distance, p.z = z, p.classification = classification;
    return p;
}

// Pixels of `colour` in the rectangle [x0, x1) x [y0, y1).
int count(const render::RgbaImage& image, int x0, int y0, int x1, int y1, std::uint32_t colour) {
    int n = 0;
    for (int y = std::max(0, y0); y < std::min(image.height, y1); ++y) {
        for (int x = std::max(0, x0); x < std::min(image.width, x1); ++x) n += image.at(x, y) == colour;
    }
    return n;
}

// Where a point lands: the top left pixel of its 2 x 2 dot, found by its colour.
std::pair<int, int> dot_of(const render::RgbaImage& image, std::uint32_t colour) {
    for (int y = 0; y < image.height; ++y) {
        for (int x = 0; x < image.width; ++x) {
            if (image.at(x, y) == colour) return {x, y};
        }
    }
    return {-1, -1};
}

const Corridor kLine{0, 0, 100, 0, 2};

TEST(ProfileImage, TrueScaleByDefault) {
    Profile p;
    p.points = {point(0, 100, 5), point(100, 150, 6)};
    ProfileImageScale s;
    const auto image = profile_image(p, kLine, ProfileImageOptions{}, &s);
    EXPECT_DOUBLE_EQ(s.px_per_z, s.px_per_distance);
    EXPECT_NEAR(s.exaggeration, 1, 1e-12);
    const auto [x0, y0] = dot_of(image, render::classification_colour(5));
    const auto [x1, y1] = dot_of(image, render::classification_colour(6));
    ASSERT_GE(x0, 0);
    ASSERT_GE(x1, 0);
    EXPECT_NEAR(double(y0 - y1) / (x1 - x0), 0.5, 0.01);  // 50 up over 100 along, as on the ground
    EXPECT_LE(image.width, 1600);
    EXPECT_LT(image.height, image.width);  // not the fixed 600 rows of before: as tall as the heights need

    ProfileImageOptions o;
    o.exaggeration = 3;
    profile_image(p, kLine, o, &s);
    EXPECT_NEAR(s.px_per_z / s.px_per_distance, 3, 1e-9);
    EXPECT_NEAR(s.exaggeration, 3, 1e-9);
    o.exaggeration = 0;
    EXPECT_THROW(profile_image(p, kLine, o), Error);
}

// Heights in feet over distances in metres: a foot of height is 0.3048 of a metre of distance.
TEST(ProfileImage, TrueScaleAcrossUnits) {
    dataset::Frame frame;
    frame.xy_to_metres = 1, frame.z_to_metres = las::kFootMetres;
    const ProfileImageOptions o = profile_png_options(frame);
    EXPECT_EQ(o.distance_unit, "m");
    EXPECT_EQ(o.z_unit, "ft");
    Profile p;
    p.points = {point(0, 100, 2), point(100, 300, 2)};
    ProfileImageScale s;
    profile_image(p, kLine, o, &s);
    EXPECT_NEAR(s.px_per_z / s.px_per_distance, las::kFootMetres, 1e-9);
    EXPECT_NEAR(s.exaggeration, 1, 1e-9);
    frame.xy_to_metres = frame.z_to_metres = las::kUsSurveyFootMetres;
    EXPECT_EQ(profile_png_options(frame).z_unit, "US ft");
}

// A cliff (a short line, a tall drop) keeps its scale: the plot is drawn narrower, not taller than 1200 rows.
TEST(ProfileImage, SteepProfileIsNarrowerNotDistorted) {
    Profile p;
    p.points = {point(0, 0, 2), point(10, 500, 2)};
    ProfileImageScale s;
    const auto image = profile_image(p, {0, 0, 10, 0, 2}, ProfileImageOptions{}, &s);
    EXPECT_NEAR(s.px_per_z, s.px_per_distance, 1e-9);
    EXPECT_LT(image.width, 400);
    EXPECT_LE(image.height, 1400);
}

// Tick values under the distance axis and left of the height axis, the titles, and the caption
// above the plot: text pixels in each margin. The bare panel image has none.
TEST(ProfileImage, AxesAreLabelled) {
    Profile p;
    p.points = {point(0, 100, 2), point(100, 150, 2)};
    ProfileImageScale s;
    const auto image = profile_image(p, kLine, ProfileImageOptions{}, &s);
    const int h = image.height;  // the margins: 58 rows below the plot, 30 above, the titles 8 from the edge
    EXPECT_GT(count(image, 0, h - 24, image.width, h, kText), 100) << "the distance axis's title";
    EXPECT_GT(count(image, 0, h - 46, image.width, h - 28, kText), 40) << "the distance ticks' values";
    EXPECT_GT(count(image, 0, 30, 26, h - 60, kText), 60) << "the height axis's title, turned";
    EXPECT_GT(count(image, 26, 30, 100, h - 60, kText), 40) << "the height ticks' values";
    EXPECT_GT(count(image, 0, 0, image.width, 28, kText), 60) << "the caption";
    const auto bare = profile_image(p, kLine, 800, 300, &s);
    EXPECT_EQ(bare.width, 800);
    EXPECT_EQ(bare.height, 300);
    EXPECT_EQ(count(bare, 0, 0, bare.width, bare.height, kText), 0);
}

// Ground is drawn last: over a vegetation point at the same place, whichever comes first in the file.
TEST(ProfileImage, GroundOnTop) {
    const std::uint32_t ground = render::classification_colour(2), trees = render::classification_colour(5);
    for (const bool ground_first : {true, false}) {
        Profile p;
        p.points = {point(50, 120, ground_first ? 2 : 5), point(50, 120, ground_first ? 5 : 2), point(0, 100, 1),
                    point(100, 140, 1)};
        const auto image = profile_image(p, kLine, ProfileImageOptions{});
        EXPECT_GE(dot_of(image, ground).first, 0) << ground_first;
        EXPECT_EQ(dot_of(image, trees).first, -1) << ground_first;
    }
    EXPECT_LT(profile_draw_rank(7), profile_draw_rank(5));  // noise lowest
    EXPECT_LT(profile_draw_rank(5), profile_draw_rank(1));
    EXPECT_LT(profile_draw_rank(1), profile_draw_rank(6));
    EXPECT_LT(profile_draw_rank(6), profile_draw_rank(2));
    EXPECT_LT(profile_draw_rank(9), profile_draw_rank(2));
    for (int c = 0; c < 256; ++c) EXPECT_LE(profile_draw_rank(static_cast<std::uint8_t>(c)), profile_draw_rank(2));
}

}  // namespace
}  // namespace lidarscout::pipelines
