// Splatting baseline: one point gives Gaussian weights (and its value within the radius, NaN
// beyond), a constant field stays constant, points sharing a texel are averaged first.
#include <gtest/gtest.h>

#include <cmath>

#include "recon/splat.hpp"
#include "recon_test_util.hpp"

namespace lidarscout::recon {
namespace {

constexpr double kUnit = static_cast<double>(kGridUnitsPerTexel);

PointValues one_channel(std::vector<float> v) { return PointValues{1, v.size(), std::move(v)}; }

TEST(ReconSplat, SinglePointGivesGaussianWeights) {
    const std::vector<GridXY> points{{40.3 * kUnit, 50.9 * kUnit}};  // texel (row 50, col 40)
    const SplatResult out = splat(points, one_channel({0.25f}), 96);
    for (int row = 0; row < 96; ++row) {
        for (int col = 0; col < 96; ++col) {
            const int dx = col - 40, dy = row - 50;
            if (std::abs(dx) <= 16 && std::abs(dy) <= 16) {
                const double w = std::exp(-(dx * dx + dy * dy) / (2 * 2.25 * 2.25));
                EXPECT_NEAR(out.weights.at(row, col), w, 1e-6 * w) << row << "," << col;
                EXPECT_EQ(out.values.at(row, col), 0.25f);
            } else {
                EXPECT_EQ(out.weights.at(row, col), 0.0f);
                EXPECT_TRUE(std::isnan(out.values.at(row, col)));
            }
        }
    }
}

TEST(ReconSplat, ConstantFieldStaysConstant) {
    const auto points = test::random_window(370, 2, [](double, double) { return 0.0; });
    std::vector<GridXY> xy;
    for (const auto& p : points) xy.push_back({std::round(p.x / 10.0 * kUnit), std::round(p.y / 10.0 * kUnit)});
    const std::vector<float> v(xy.size(), 0.375f);
    const PointValues values{3, xy.size(), [&] {
                                 std::vector<float> all(3 * xy.size(), 0.375f);
                                 return all;
                             }()};
    const SplatResult out = splat(xy, values, 96);
    for (const float x : out.values.values) EXPECT_NEAR(x, 0.375f, 1e-6);
    EXPECT_EQ(out.values.channels, 3);
}

TEST(ReconSplat, TexelMeanFirstAndEdges) {
    // Two points in one texel (0.1, 0.3) and one far away (0.9): the texel mean 0.2 counts once.
    const std::vector<GridXY> points{
        {10.2 * kUnit, 10.2 * kUnit}, {10.8 * kUnit, 10.9 * kUnit}, {12.5 * kUnit, 10.5 * kUnit}};
    const SplatResult out = splat(points, one_channel({0.1f, 0.3f, 0.9f}), 96);
    const double w0 = std::exp(-(1.0 * 1.0) / (2 * 2.25 * 2.25)), w2 = std::exp(-(1.0) / (2 * 2.25 * 2.25));
    // Texel (10, 11) is 1 texel from both occupied texels (10,10) and (10,12).
    EXPECT_NEAR(out.values.at(10, 11), (w0 * 0.2 + w2 * 0.9) / (w0 + w2), 1e-6);
    EXPECT_NEAR(out.values.at(10, 10), (0.2 + std::exp(-4.0 / (2 * 2.25 * 2.25)) * 0.9) /
                                           (1.0 + std::exp(-4.0 / (2 * 2.25 * 2.25))), 1e-6);
    // A point on the window's max corner falls into the last texel.
    const std::vector<GridXY> corner{{96 * kUnit, 96 * kUnit}};
    const SplatResult c = splat(corner, one_channel({1.0f}), 96);
    EXPECT_FLOAT_EQ(c.weights.at(95, 95), 1.0f);
}

}  // namespace
}  // namespace lidarscout::recon
