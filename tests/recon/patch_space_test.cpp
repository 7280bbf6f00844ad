// Patch space: window geometry, snapping and the window's edges, normalisation (median centre
// height, radius), merging of duplicates, order independence, status, errors, cropping.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>

#include "core/error.hpp"
#include "recon/patch_space.hpp"
#include "recon_test_util.hpp"

namespace lidarscout::recon {
namespace {

using test::kPatchMin;
using test::make_patch;

lidarscout::OverviewPoint pt(double x, double y, double z, lidarscout::Rgb8 rgb = {}) {
    lidarscout::OverviewPoint p;
    p.x = x;
    p.y = y;
    p.z = z;
    p.rgb = rgb;
    return p;
}

TEST(ReconPatchSpace, DefaultGeometry) {
    const PatchSpec spec;
    EXPECT_EQ(spec.window_texels(), 96);
    EXPECT_DOUBLE_EQ(spec.patch_m(), 640.0);
    EXPECT_DOUBLE_EQ(spec.pad_m(), 160.0);
    EXPECT_DOUBLE_EQ(spec.window_m(), 960.0);
    EXPECT_DOUBLE_EQ(spec.radius_m(), 480.0);
    EXPECT_EQ(spec.grid_extent(), 96 * 65536);

    const PatchSpec fine{2.5, 64, 16};
    EXPECT_DOUBLE_EQ(fine.patch_m(), 160.0);
    EXPECT_DOUBLE_EQ(fine.radius_m(), 120.0);
}

TEST(ReconPatchSpace, RejectsBadSpecAndPoints) {
    EXPECT_THROW((PatchSpec{0.0, 64, 16}.validate()), Error);
    EXPECT_THROW((PatchSpec{NAN, 64, 16}.validate()), Error);
    EXPECT_THROW((PatchSpec{10.0, 0, 16}.validate()), Error);
    EXPECT_THROW((PatchSpec{10.0, 64, -1}.validate()), Error);
    EXPECT_THROW((PatchSpec{1.0, 500, 16}.validate()), Error);
    EXPECT_NO_THROW((PatchSpec{1.0, 480, 16}.validate()));
    const std::vector<lidarscout::OverviewPoint> bad{pt(100, 100, NAN)};
    EXPECT_THROW(make_patch(bad), Error);
}

TEST(ReconPatchSpace, WindowEdgesAndPatchCoordinates) {
    // Window of the patch at (160, 160): [0, 960)^2.
    const std::vector<lidarscout::OverviewPoint> points{
        pt(0.0, 0.0, 1),        // min corner: inside
        pt(480.0, 480.0, 2),    // centre
        pt(959.999, 10.0, 3),   // just inside
        pt(960.0, 10.0, 4),     // max edge: outside
        pt(-0.001, 10.0, 5),    // outside
        pt(10.0, 960.0, 6),     // outside
    };
    const PatchPoints p = make_patch(points, test::opts(1));
    EXPECT_EQ(p.window_count, 3u);
    ASSERT_EQ(p.points.size(), 3u);
    EXPECT_DOUBLE_EQ(p.window_min_x, 0.0);
    EXPECT_DOUBLE_EQ(p.window_min_y, 0.0);
    // Sorted by (gy, gx): (0,0), (959.999, 10), (480, 480).
    EXPECT_EQ(p.points[0].gx, 0);
    EXPECT_DOUBLE_EQ(p.patch_x(p.points[0]), -1.0);
    EXPECT_DOUBLE_EQ(p.patch_y(p.points[0]), -1.0);
    EXPECT_EQ(p.points[2].gx, 48 * 65536);
    EXPECT_DOUBLE_EQ(p.patch_x(p.points[2]), 0.0);
    EXPECT_DOUBLE_EQ(p.patch_y(p.points[2]), 0.0);
    EXPECT_NEAR(p.patch_x(p.points[1]), 959.999 / 480.0 - 1.0, 2e-7);  // snapped to 1/65536 texel
    EXPECT_NEAR(p.patch_y(p.points[1]), 10.0 / 480.0 - 1.0, 2e-7);
    // Snapping: 1/65536 texel.
    EXPECT_EQ(p.points[1].gy, std::llround(10.0 / 10.0 * 65536));
}

TEST(ReconPatchSpace, MedianCentreHeightAndNormalisation) {
    const std::vector<lidarscout::OverviewPoint> odd{pt(10, 10, 5), pt(20, 10, 100), pt(30, 10, 7)};
    const PatchPoints p = make_patch(odd, test::opts(1));
    EXPECT_DOUBLE_EQ(p.centre_z, 7.0);
    ASSERT_EQ(p.points.size(), 3u);
    EXPECT_FLOAT_EQ(p.points[0].h, static_cast<float>((5.0 - 7.0) / 480.0));
    EXPECT_FLOAT_EQ(p.points[1].h, static_cast<float>((100.0 - 7.0) / 480.0));
    EXPECT_DOUBLE_EQ(p.to_metres(p.normalise(123.25)), 123.25);
    EXPECT_NEAR(p.to_metres(p.points[1].h), 100.0, 1e-4);

    const std::vector<lidarscout::OverviewPoint> even{pt(10, 10, 5), pt(20, 10, 100), pt(30, 10, 7), pt(40, 10, 9)};
    EXPECT_DOUBLE_EQ(make_patch(even, test::opts(1)).centre_z, 8.0);
}

TEST(ReconPatchSpace, DuplicatesMergedAndColourScaled) {
    const std::vector<lidarscout::OverviewPoint> points{pt(100, 100, 10, {255, 0, 10}), pt(100, 100, 20, {0, 0, 20}),
                                                     pt(300, 100, 30, {51, 102, 204})};
    const PatchPoints p = make_patch(points, test::opts(1));
    EXPECT_EQ(p.window_count, 3u);
    ASSERT_EQ(p.points.size(), 2u);
    EXPECT_DOUBLE_EQ(p.centre_z, 22.5);  // median of the merged heights 15 and 30
    EXPECT_FLOAT_EQ(p.points[0].h, static_cast<float>((15.0 - 22.5) / 480.0));
    EXPECT_FLOAT_EQ(p.points[0].r, 0.5f);
    EXPECT_FLOAT_EQ(p.points[0].b, 15.0f / 255.0f);
    EXPECT_FLOAT_EQ(p.points[1].g, 0.4f);

    const PatchPoints gray = make_patch(points, test::opts(1, false));
    EXPECT_TRUE(std::isnan(gray.points[0].r));
    EXPECT_TRUE(std::isnan(colour_values(gray).value(2, 1)));
}

TEST(ReconPatchSpace, IndependentOfInputOrder) {
    auto points = test::random_window(400, 7, test::terrain);
    points.push_back(points[3]);  // a duplicate
    points.back().z += 1.0;
    const PatchPoints a = make_patch(points);
    std::mt19937_64 rng(99);
    std::shuffle(points.begin(), points.end(), rng);
    const PatchPoints b = make_patch(points);
    ASSERT_EQ(a.points.size(), b.points.size());
    EXPECT_EQ(a.points.size(), 400u);
    EXPECT_EQ(a.centre_z, b.centre_z);
    for (std::size_t i = 0; i < a.points.size(); ++i) {
        EXPECT_EQ(a.points[i].gx, b.points[i].gx);
        EXPECT_EQ(a.points[i].gy, b.points[i].gy);
        EXPECT_EQ(a.points[i].h, b.points[i].h);
        EXPECT_EQ(a.points[i].r, b.points[i].r);
    }
}

TEST(ReconPatchSpace, TooFewPointsIsMarked) {
    const auto points = test::random_window(24, 3, test::terrain);
    EXPECT_EQ(make_patch(points).status, PatchStatus::TooFewPoints);
    EXPECT_EQ(make_patch(points, test::opts(24)).status, PatchStatus::Ok);
    EXPECT_EQ(make_patch({}, test::opts(0)).status, PatchStatus::TooFewPoints);
    EXPECT_TRUE(std::isnan(make_patch({}).centre_z));
}

TEST(ReconPatchSpace, FromPatchGridMatchesWindow) {
    lidarscout::PatchGrid grid(1000.0, 2000.0, 640.0);
    const auto points = test::random_window(3000, 11, test::terrain);
    for (const auto& p : points) {
        // Spread over a 3 x 3 block of cells around cell (0, 0): shift the 960 m window frame.
        grid.add(1000.0 - 640.0 + p.x * 2.0, 2000.0 - 640.0 + p.y * 2.0, p.z, p.rgb, 0, 2, 0);
    }
    const lidarscout::CellKey cell{0, 0};
    const PatchPoints from_grid = make_patch_points(grid, cell);
    const auto window = grid.window(cell, 160.0);
    const PatchPoints direct = make_patch_points(window, 1000.0, 2000.0);
    EXPECT_GT(from_grid.points.size(), 300u);
    ASSERT_EQ(from_grid.points.size(), direct.points.size());
    EXPECT_EQ(from_grid.window_count, window.size());
    for (std::size_t i = 0; i < direct.points.size(); ++i) EXPECT_EQ(from_grid.points[i].gx, direct.points[i].gx);

    lidarscout::PatchGrid other(0.0, 0.0, 320.0);
    EXPECT_THROW(make_patch_points(other, cell), Error);
}

TEST(ReconPatchSpace, CropCentre) {
    Image image(96, 2);
    for (int c = 0; c < 2; ++c) {
        for (int r = 0; r < 96; ++r) {
            for (int col = 0; col < 96; ++col) image.at(r, col, c) = static_cast<float>(c * 10000 + r * 100 + col);
        }
    }
    const Image crop = crop_centre(image, 64);
    EXPECT_EQ(crop.size, 64);
    EXPECT_EQ(crop.channels, 2);
    EXPECT_EQ(crop.at(0, 0, 0), 16 * 100 + 16);
    EXPECT_EQ(crop.at(63, 5, 1), 10000 + 79 * 100 + 21);
    EXPECT_THROW(crop_centre(image, 97), Error);
    EXPECT_THROW(crop_centre(image, 63), Error);
}

}  // namespace
}  // namespace lidarscout::recon
