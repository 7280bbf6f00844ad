// Algorithm 1 outputs: linear reproduces a plane inside the real triangles, nearest images hold
// the nearest chunk point's values, linear falls back to nearest outside, colour handling,
// marked patches, determinism and the row order (row 0 = south).
#include <gtest/gtest.h>

#include <cmath>

#include "recon/grid_geometry.hpp"
#include "recon/interpolation.hpp"
#include "recon_test_util.hpp"

namespace lidarscout::recon {
namespace {

// Window-frame metres of a texel centre.
double texel_metres(int i) { return (i + 0.5) * 10.0; }

TEST(ReconInterpolation, LinearIsExactOnAPlane) {
    const auto plane = [](double x, double y) { return 250.0 + 0.31 * x - 0.17 * y; };
    for (const std::uint64_t seed : {1u, 2u}) {
        const PatchPoints patch = test::make_patch(test::random_window(370, seed, plane));
        const InterpolatedPatch out = interpolate_patch(patch);
        ASSERT_EQ(out.status, PatchStatus::Ok);
        ASSERT_EQ(out.height_linear.size, 96);
        int inside = 0;
        for (int row = 0; row < 96; ++row) {
            for (int col = 0; col < 96; ++col) {
                if (out.face_map.at(row, col) < 0) continue;
                ++inside;
                const double expected = patch.normalise(plane(patch.texel_centre_x(col), patch.texel_centre_y(row)));
                EXPECT_NEAR(out.height_linear.at(row, col), expected, 1e-5) << row << "," << col;
            }
        }
        EXPECT_GT(inside, 96 * 96 * 8 / 10);
    }
}

TEST(ReconInterpolation, LinearColourIsExactOnAPlane) {
    // Colours linear in position: r = x / 960 * 255 (as 8-bit, so only where the values are
    // exact integers: points on a 96 m lattice with r = x / 4 exactly).
    std::vector<lidarscout::OverviewPoint> points;
    for (int j = 0; j < 10; ++j) {
        for (int i = 0; i < 10; ++i) {
            lidarscout::OverviewPoint p;
            p.x = i * 96.0 + 13.0;
            p.y = j * 96.0 + 7.0;
            p.z = 100.0;
            p.rgb = {static_cast<std::uint8_t>(i * 24), static_cast<std::uint8_t>(j * 24), 200};
            points.push_back(p);
        }
    }
    const InterpolatedPatch out = interpolate_patch(test::make_patch(points));
    for (int row = 0; row < 96; ++row) {
        for (int col = 0; col < 96; ++col) {
            if (out.face_map.at(row, col) < 0) continue;
            EXPECT_NEAR(out.rgb_linear.at(row, col, 0), (texel_metres(col) - 13.0) / 96.0 * 24.0 / 255.0, 1e-5);
            EXPECT_NEAR(out.rgb_linear.at(row, col, 1), (texel_metres(row) - 7.0) / 96.0 * 24.0 / 255.0, 1e-5);
            EXPECT_NEAR(out.rgb_linear.at(row, col, 2), 200.0 / 255.0, 1e-6);
        }
    }
}

TEST(ReconInterpolation, NearestHoldsTheClosestPointAndLinearFallsBackOutside) {
    // Points only in the middle: a large outside region.
    auto points = test::random_window(300, 3, test::terrain);
    std::erase_if(points, [](const auto& p) { return std::hypot(p.x - 480.0, p.y - 500.0) > 300.0; });
    const PatchPoints patch = test::make_patch(points);
    ASSERT_EQ(patch.status, PatchStatus::Ok);
    const auto positions = grid_positions(patch);
    const InterpolatedPatch out = interpolate_patch(patch);
    int outside = 0;
    for (int row = 0; row < 96; ++row) {
        for (int col = 0; col < 96; ++col) {
            const std::int32_t n = test::brute_nearest(positions, {texel_centre(col), texel_centre(row)});
            const PatchPoint& p = patch.points[n];
            EXPECT_EQ(out.height_nearest.at(row, col), p.h);
            EXPECT_EQ(out.rgb_nearest.at(row, col, 0), p.r);
            EXPECT_EQ(out.rgb_nearest.at(row, col, 1), p.g);
            EXPECT_EQ(out.rgb_nearest.at(row, col, 2), p.b);
            if (out.face_map.at(row, col) < 0) {
                ++outside;
                EXPECT_EQ(out.height_linear.at(row, col), p.h);
                EXPECT_EQ(out.rgb_linear.at(row, col, 1), p.g);
            }
            EXPECT_TRUE(std::isfinite(out.height_linear.at(row, col)));
        }
    }
    EXPECT_GT(outside, 2000);
}

TEST(ReconInterpolation, RowZeroIsSouth) {
    std::vector<lidarscout::OverviewPoint> points;
    for (int i = 0; i < 30; ++i) {
        points.push_back(test::point_at(5.0 + i * 30.0, 5.0, [](double, double) { return 0.0; }));     // south row
        points.push_back(test::point_at(5.0 + i * 30.0, 955.0, [](double, double) { return 96.0; }));  // north row
    }
    const PatchPoints patch = test::make_patch(points);
    const InterpolatedPatch out = interpolate_patch(patch);
    EXPECT_LT(out.height_nearest.at(0, 40), out.height_nearest.at(95, 40));
    EXPECT_FLOAT_EQ(out.height_nearest.at(0, 40), static_cast<float>((0.0 - patch.centre_z) / 480.0));
    // Linear between the rows: rises northwards linearly.
    EXPECT_NEAR(patch.to_metres(out.height_linear.at(47, 40)), 96.0 * (475.0 - 5.0) / 950.0, 1e-3);
}

TEST(ReconInterpolation, NoColourGivesNaNAndTooFewPointsGivesNothing) {
    const auto points = test::random_window(100, 4, test::terrain);
    const InterpolatedPatch grey = interpolate_patch(test::make_patch(points, test::opts(25, false)));
    ASSERT_EQ(grey.status, PatchStatus::Ok);
    EXPECT_EQ(grey.rgb_linear.channels, 3);
    for (const float v : grey.rgb_linear.values) EXPECT_TRUE(std::isnan(v));
    for (const float v : grey.rgb_nearest.values) EXPECT_TRUE(std::isnan(v));
    for (const float v : grey.height_linear.values) EXPECT_TRUE(std::isfinite(v));

    const InterpolatedPatch few = interpolate_patch(test::make_patch(test::random_window(10, 4, test::terrain)));
    EXPECT_EQ(few.status, PatchStatus::TooFewPoints);
    EXPECT_TRUE(few.height_linear.empty());
    EXPECT_TRUE(few.height_nearest.empty());
    EXPECT_TRUE(few.rgb_linear.empty());
    EXPECT_TRUE(few.face_map.face.empty());
}

TEST(ReconInterpolation, DeterministicBytes) {
    std::vector<lidarscout::OverviewPoint> points = test::random_window(370, 6, test::terrain);
    for (int j = 0; j < 8; ++j) {  // plus a cocircular lattice (ambiguous Delaunay diagonals)
        for (int i = 0; i < 8; ++i) points.push_back(test::point_at(100.0 + i * 40.0, 100.0 + j * 40.0, test::terrain));
    }
    const PatchPoints patch = test::make_patch(points);
    const InterpolatedPatch a = interpolate_patch(patch);
    for (int run = 0; run < 3; ++run) {
        const InterpolatedPatch b = interpolate_patch(patch);
        EXPECT_TRUE(test::same_bytes(a.height_linear, b.height_linear));
        EXPECT_TRUE(test::same_bytes(a.height_nearest, b.height_nearest));
        EXPECT_TRUE(test::same_bytes(a.rgb_linear, b.rgb_linear));
        EXPECT_TRUE(test::same_bytes(a.rgb_nearest, b.rgb_nearest));
        EXPECT_EQ(a.face_map.face, b.face_map.face);
    }
}

}  // namespace
}  // namespace lidarscout::recon
