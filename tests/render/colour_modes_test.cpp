// Colour modes: names, the elevation ramp, ASPRS class colours, the intensity ramp and its
// automatic range.
#include <gtest/gtest.h>

#include <set>
#include <string>
#include <vector>

#include "core/error.hpp"
#include "render/colour_modes.hpp"
#include "render/framebuffer.hpp"

namespace lidarscout::render {
namespace {

int luminance(std::uint32_t c) { return 299 * red(c) + 587 * green(c) + 114 * blue(c); }

TEST(RenderColourModes, NamesRoundTripAndUnknownNamesAreListed) {
    for (const ColourMode m :
         {ColourMode::Rgb, ColourMode::Elevation, ColourMode::Intensity, ColourMode::Classification}) {
        EXPECT_EQ(parse_colour_mode(colour_mode_name(m)), m);
    }
    EXPECT_EQ(parse_colour_mode("elevation"), ColourMode::Elevation);
    try {
        parse_colour_mode("height");
        FAIL();
    } catch (const Error& e) {
        const std::string what = e.what();
        EXPECT_NE(what.find("height"), std::string::npos) << what;
        for (const char* known : {"rgb", "elevation", "intensity", "classification"}) {
            EXPECT_NE(what.find(known), std::string::npos) << what;
        }
    }
    EXPECT_THROW(parse_colour_mode("RGB"), Error);
}

TEST(RenderColourModes, ElevationRampRisesInLightnessAndClamps) {
    std::set<std::uint32_t> distinct;
    int previous = -1, rises = 0;
    for (int k = 0; k <= 20; ++k) {
        const std::uint32_t c = elevation_ramp(k / 20.0f);
        distinct.insert(c);
        if (luminance(c) > previous) ++rises;
        previous = luminance(c);
    }
    EXPECT_GE(distinct.size(), 20u);
    EXPECT_EQ(rises, 21);  // lightness rises monotonically
    EXPECT_GT(luminance(elevation_ramp(1.0f)), 3 * luminance(elevation_ramp(0.0f)));
    EXPECT_EQ(elevation_ramp(-3.0f), elevation_ramp(0.0f));
    EXPECT_EQ(elevation_ramp(7.0f), elevation_ramp(1.0f));
}

TEST(RenderColourModes, PaletteElevationUsesTheBatchOriginAndRange) {
    ColourSettings s;
    s.mode = ColourMode::Elevation;
    s.z_min = 100;
    s.z_max = 300;
    const Palette p(s);
    const auto map = p.elevation_map(1000.0);  // points stored relative to z = 1000
    EXPECT_EQ(map(-900.0f), elevation_ramp(0.0f + 0.5f / Palette::kRampSize));   // z = 100
    EXPECT_EQ(map(-800.0f), elevation_ramp(0.5f + 0.5f / Palette::kRampSize));   // z = 200
    EXPECT_EQ(map(-1000.0f), map(-900.0f));                                      // below: clamped
    EXPECT_EQ(map(0.0f), map(-700.0f));                                           // above: clamped
    EXPECT_EQ(map(-700.0f), elevation_ramp(1.0f - 0.5f / Palette::kRampSize));    // z = 300
    EXPECT_NE(map(-900.0f), map(-750.0f));
}

TEST(RenderColourModes, AsprsClassesHaveTheirUsualHues) {
    const auto ground = classification_colour(2), high_veg = classification_colour(5);
    const auto building = classification_colour(6), water = classification_colour(9);
    EXPECT_GT(red(ground), green(ground));
    EXPECT_GT(green(ground), blue(ground));  // brown
    for (const int veg : {3, 4, 5}) {
        const auto c = classification_colour(static_cast<std::uint8_t>(veg));
        EXPECT_GT(green(c), red(c)) << veg;
        EXPECT_GT(green(c), blue(c)) << veg;
    }
    EXPECT_LT(luminance(high_veg), luminance(classification_colour(3)));  // tall = darker green
    EXPECT_GT(red(building), green(building));
    EXPECT_GT(red(building), blue(building));
    EXPECT_GT(blue(water), red(water));
    EXPECT_GT(blue(water), green(water));
    std::set<std::uint32_t> standard;
    for (int c = 0; c <= 22; ++c) standard.insert(classification_colour(static_cast<std::uint8_t>(c)));
    EXPECT_EQ(standard.size(), 23u);
    EXPECT_NE(classification_colour(64), classification_colour(65));
    ColourSettings s;
    s.mode = ColourMode::Classification;
    EXPECT_EQ(Palette(s).classification(6), building);
}

TEST(RenderColourModes, IntensityIsAGreyRampWithRangeAndGamma) {
    ColourSettings s;
    s.mode = ColourMode::Intensity;
    s.intensity_min = 1000;
    s.intensity_max = 3000;
    const Palette linear(s);
    EXPECT_EQ(linear.intensity(0), pack_rgba(0, 0, 0));
    EXPECT_EQ(linear.intensity(1000), pack_rgba(0, 0, 0));
    EXPECT_EQ(linear.intensity(65535), pack_rgba(255, 255, 255));
    const auto mid = linear.intensity(2000);
    EXPECT_EQ(red(mid), green(mid));
    EXPECT_EQ(green(mid), blue(mid));
    EXPECT_NEAR(red(mid), 128, 1);
    int previous = -1;
    for (int v = 0; v <= 4000; v += 50) {
        EXPECT_GE(red(linear.intensity(static_cast<std::uint16_t>(v))), previous);
        previous = red(linear.intensity(static_cast<std::uint16_t>(v)));
    }
    s.intensity_gamma = 2.0f;
    EXPECT_NEAR(red(Palette(s).intensity(2000)), 180, 1);  // sqrt(0.5) * 255
}

TEST(RenderColourModes, AutoIntensityRangeSkipsOutliers) {
    std::vector<PointAttr> points(1000);
    for (std::size_t i = 0; i < points.size(); ++i) points[i].intensity = static_cast<std::uint16_t>(100 + i);
    points[0].intensity = 0;
    points[999].intensity = 65535;
    const PointBatch batch{0, 0, 0, points};
    const auto range = auto_intensity_range(std::span(&batch, 1));
    EXPECT_NEAR(range[0], 100 + 20, 2);
    EXPECT_NEAR(range[1], 100 + 979, 2);
    EXPECT_EQ(auto_intensity_range({}), (std::array<float, 2>{0.0f, 65535.0f}));
}

TEST(RenderColourModes, PaletteRejectsEmptyRanges) {
    ColourSettings s;
    s.z_min = s.z_max = 5;
    EXPECT_THROW(Palette{s}, Error);
    s = {};
    s.intensity_max = s.intensity_min;
    EXPECT_THROW(Palette{s}, Error);
    s = {};
    s.intensity_gamma = 0;
    EXPECT_THROW(Palette{s}, Error);
}

}  // namespace
}  // namespace lidarscout::render
