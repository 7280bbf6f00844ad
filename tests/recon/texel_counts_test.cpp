// TexelCounts: square counts against a brute-force count, the dilation of a mask, the bounding
// boxes a disc meets, and the half-plane test (a centre beside its points, or among them).
#include "recon/texel_counts.hpp"

#include <gtest/gtest.h>

#include <random>
#include <vector>

#include "core/error.hpp"

namespace lidarscout::recon {
namespace {

constexpr double kUnit = 100;  // grid units a texel

TEST(TexelCounts, SquaresCountWhatWasAdded) {
    const int side = 40;
    TexelCounts counts(side, kUnit);
    std::vector<int> brute(side * side, 0);
    std::mt19937 rng(5);
    std::uniform_int_distribution<int> texel(0, side - 1);
    for (int i = 0; i < 3000; ++i) {
        const int c = texel(rng), r = texel(rng);
        EXPECT_EQ(counts.add(c, r, (c + 0.5) * kUnit, (r + 0.5) * kUnit), ++brute[r * side + c]);
    }
    counts.summed();
    for (const int radius : {0, 1, 3, 50}) {
        for (int r = -2; r < side + 2; r += 3) {
            for (int c = -2; c < side + 2; c += 5) {
                std::int64_t expected = 0;
                for (int rr = std::max(r - radius, 0); rr <= std::min(r + radius, side - 1); ++rr) {
                    for (int cc = std::max(c - radius, 0); cc <= std::min(c + radius, side - 1); ++cc) {
                        expected += brute[rr * side + cc];
                    }
                }
                EXPECT_EQ(counts.around(c, r, radius), expected) << c << ", " << r << " within " << radius;
            }
        }
    }
}

TEST(TexelCounts, ADiscMeetsATexelWhereItsPointsAre) {
    TexelCounts counts(10, kUnit);
    counts.add(4, 4, 410, 420);  // the texel spans [400, 500]^2; its points [410, 450] x [420, 430]
    counts.add(4, 4, 450, 430);
    counts.summed();
    EXPECT_TRUE(counts.meets_disc(4, 4, 430, 425, 1));       // between its points
    EXPECT_TRUE(counts.meets_disc(4, 4, 300, 425, 110));     // reaches x 410
    EXPECT_FALSE(counts.meets_disc(4, 4, 300, 425, 109));    // stops short of it
    EXPECT_FALSE(counts.meets_disc(4, 4, 490, 490, 50));     // the texel's empty corner
    EXPECT_FALSE(counts.meets_disc(5, 4, 550, 450, 1000));   // no point in that texel
    EXPECT_THROW(TexelCounts(0, kUnit), Error);
}

TEST(TexelCounts, ACentreBesideItsPointsIsFoundAndOneAmongThemIsNot) {
    const int side = 30;
    TexelCounts counts(side, kUnit);
    // points on the west half (columns 0..14), and one in the east half of texel (15, 15)
    for (int r = 0; r < side; ++r) {
        for (int c = 0; c < 15; ++c) counts.add(c, r, (c + 0.3) * kUnit, (r + 0.6) * kUnit);
    }
    counts.add(15, 15, 15.8 * kUnit, 15.5 * kUnit);
    counts.summed();
    EXPECT_TRUE(counts.beside(20, 10, 10));   // every point within 10 texels lies west of it
    EXPECT_TRUE(counts.beside(16, 10, 10));   // the east point is 5 rows up and still west of x 16.5
    EXPECT_TRUE(counts.beside(16, 15, 2));    // (15.8, 15.5) lies west of its centre (16.5, 15.5) too
    EXPECT_FALSE(counts.beside(10, 10, 3));   // among the points
    EXPECT_FALSE(counts.beside(15, 15, 3));   // its own texel has a point east of its centre, others west
    EXPECT_TRUE(counts.beside(25, 25, 3));    // nothing near at all
}

}  // namespace
}  // namespace lidarscout::recon
