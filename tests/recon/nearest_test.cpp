// Nearest-point map against brute force (lowest index among equally near points) on random,
// clustered, lattice (many exact ties) and tiny inputs, and other window sizes.
#include <gtest/gtest.h>

#include <random>

#include "recon/grid_geometry.hpp"
#include "recon/nearest.hpp"
#include "recon_test_util.hpp"

namespace lidarscout::recon {
namespace {

constexpr double kUnit = static_cast<double>(kGridUnitsPerTexel);

void check(const std::vector<GridXY>& points, int size) {
    const auto map = nearest_point_map(points, size);
    ASSERT_EQ(map.size(), static_cast<std::size_t>(size) * size);
    for (int row = 0; row < size; ++row) {
        for (int col = 0; col < size; ++col) {
            EXPECT_EQ(map[static_cast<std::size_t>(row) * size + col],
                      test::brute_nearest(points, {texel_centre(col), texel_centre(row)}))
                << "texel " << row << "," << col;
        }
    }
}

TEST(ReconNearest, RandomInputsMatchBruteForce) {
    for (const std::uint64_t seed : {1u, 2u, 3u}) {
        std::mt19937_64 rng(seed);
        std::uniform_int_distribution<std::int64_t> u(0, 96 * kGridUnitsPerTexel);
        std::vector<GridXY> points;
        for (int i = 0; i < 370; ++i) points.push_back({static_cast<double>(u(rng)), static_cast<double>(u(rng))});
        check(points, 96);
    }
}

TEST(ReconNearest, ClusteredAndSparse) {
    std::mt19937_64 rng(4);
    std::normal_distribution<double> n(20.0 * kUnit, 3.0 * kUnit);
    std::vector<GridXY> cluster;
    for (int i = 0; i < 200; ++i) {
        cluster.push_back(
            {std::clamp(std::round(n(rng)), 0.0, 96 * kUnit), std::clamp(std::round(n(rng)), 0.0, 96 * kUnit)});
    }
    check(cluster, 96);
    check({{0, 0}}, 96);
    check({{96 * kUnit, 96 * kUnit}, {0, 96 * kUnit}}, 96);
    EXPECT_EQ(nearest_point_map({}, 4), std::vector<std::int32_t>(16, -1));
}

TEST(ReconNearest, LatticeTiesTakeLowestIndex) {
    // Points at texel corners every 2 texels: every texel centre is equally near to one to
    // four points; reversed order changes which one wins.
    std::vector<GridXY> lattice;
    for (int j = 0; j <= 96; j += 2) {
        for (int i = 0; i <= 96; i += 2) lattice.push_back({i * kUnit, j * kUnit});
    }
    check(lattice, 96);
    std::reverse(lattice.begin(), lattice.end());
    check(lattice, 96);
}

TEST(ReconNearest, OtherWindowSizes) {
    std::mt19937_64 rng(8);
    for (const int size : {1, 7, 13, 150}) {
        std::uniform_int_distribution<std::int64_t> u(0, size * kGridUnitsPerTexel);
        std::vector<GridXY> points;
        for (int i = 0; i < 50; ++i) points.push_back({static_cast<double>(u(rng)), static_cast<double>(u(rng))});
        check(points, size);
    }
}

}  // namespace
}  // namespace lidarscout::recon
