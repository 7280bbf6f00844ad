// Clough-Tocher baseline: exact gradients and values on a plane, exact at the data points,
// close on a quadratic (closer than linear), C0 across triangle edges, nearest outside.
#include <gtest/gtest.h>

#include <cmath>

#include "recon/cubic.hpp"
#include "recon/grid_geometry.hpp"
#include "recon_test_util.hpp"

namespace lidarscout::recon {
namespace {

double texel_metres(int i) { return (i + 0.5) * 10.0; }

TEST(ReconCubic, PlaneGradientsAndValuesAreExact) {
    const auto plane = [](double x, double y) { return 250.0 + 0.31 * x - 0.17 * y; };
    const PatchPoints patch = test::make_patch(test::random_window(370, 1, plane));
    const PatchGeometry geometry = build_geometry(patch);
    const PointValues h = height_values(patch);
    const auto grad = estimate_gradients(geometry.triangulation, h.values, patch.spec.grid_extent());
    // d h' / d x' = (dz/dx * r) / r in patch space: the metric slope itself.
    for (std::size_t i = 0; i < grad.size(); ++i) {
        EXPECT_NEAR(grad[i][0], 0.31, 1e-4) << i;
        EXPECT_NEAR(grad[i][1], -0.17, 1e-4) << i;
    }
    const Image cubic = cubic_image(geometry, h, patch.spec.grid_extent());
    for (int row = 0; row < 96; ++row) {
        for (int col = 0; col < 96; ++col) {
            if (geometry.face_map.at(row, col) < 0) continue;
            EXPECT_NEAR(cubic.at(row, col), patch.normalise(plane(texel_metres(col), texel_metres(row))), 1e-5);
        }
    }
}

TEST(ReconCubic, ExactAtDataPointsAndCloseOnAQuadratic) {
    const auto bowl = [](double x, double y) {
        return 100.0 + 2e-4 * (x - 400.0) * (x - 400.0) + 1e-4 * (y - 520.0) * (y - 520.0) + 3e-5 * x * y;
    };
    // Points on texel centres (so the data points are sampled), jittered lattice.
    std::vector<lidarscout::OverviewPoint> points;
    std::mt19937_64 rng(3);
    std::uniform_int_distribution<int> jitter(-2, 2);
    for (int j = 2; j < 96; j += 5) {
        for (int i = 2; i < 96; i += 5) {
            const int col = std::clamp(i + jitter(rng), 0, 95), row = std::clamp(j + jitter(rng), 0, 95);
            points.push_back(test::point_at(texel_metres(col), texel_metres(row), bowl));
        }
    }
    const PatchPoints patch = test::make_patch(points);
    const PatchGeometry geometry = build_geometry(patch);
    const PointValues h = height_values(patch);
    const Image cubic = cubic_image(geometry, h, patch.spec.grid_extent());
    const Image linear = linear_image(geometry, h);
    for (const PatchPoint& p : patch.points) {
        const int col = static_cast<int>(p.gx / kGridUnitsPerTexel), row = static_cast<int>(p.gy / kGridUnitsPerTexel);
        EXPECT_NEAR(cubic.at(row, col), p.h, 1e-6);
    }
    double se_cubic = 0, se_linear = 0;
    int n = 0;
    for (int row = 0; row < 96; ++row) {
        for (int col = 0; col < 96; ++col) {
            if (geometry.face_map.at(row, col) < 0) continue;
            const double truth = patch.normalise(bowl(texel_metres(col), texel_metres(row)));
            se_cubic += std::pow(cubic.at(row, col) - truth, 2);
            se_linear += std::pow(linear.at(row, col) - truth, 2);
            ++n;
        }
    }
    const double rmse_cubic_m = std::sqrt(se_cubic / n) * 480.0, rmse_linear_m = std::sqrt(se_linear / n) * 480.0;
    EXPECT_LT(rmse_cubic_m, 0.5 * rmse_linear_m);
    EXPECT_LT(rmse_cubic_m, 0.2);  // metres, on a bowl spanning ~100 m
}

TEST(ReconCubic, ContinuousAcrossEdgesAndNearestOutside) {
    // Sampled on a fine grid the cubic has no jumps: neighbouring texels differ by at most a
    // slope-bound amount, also across triangle edges.
    auto points = test::random_window(200, 7, test::terrain);
    std::erase_if(points, [](const auto& p) { return p.x > 700.0; });
    const PatchPoints patch = test::make_patch(points);
    const PatchGeometry geometry = build_geometry(patch);
    const PointValues h = height_values(patch);
    const Image cubic = cubic_image(geometry, h, patch.spec.grid_extent());
    const Image nearest = nearest_image(geometry, h);
    for (int row = 0; row < 96; ++row) {
        for (int col = 0; col < 96; ++col) {
            const float v = cubic.at(row, col);
            ASSERT_TRUE(std::isfinite(v));
            if (geometry.face_map.at(row, col) < 0) {
                EXPECT_EQ(v, nearest.at(row, col));
            } else if (col + 1 < 96 && geometry.face_map.at(row, col + 1) >= 0) {
                EXPECT_LT(std::abs(cubic.at(row, col + 1) - v) * 480.0, 15.0) << row << "," << col;
            }
        }
    }
}

}  // namespace
}  // namespace lidarscout::recon
