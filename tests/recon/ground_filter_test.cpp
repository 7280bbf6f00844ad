// The ground filter: on a made-up scene (a sloping plane with a house and trees) the ground is
// kept and the roof and crowns are not; on real classified surveys, their classes left unread,
// it agrees with the survey's own ground class (ISPRS-style type I, type II and total errors,
// printed); parameters out of range are refused.
#include "recon/ground_filter.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <random>
#include <string>

#include "core/error.hpp"
#include "core/thread_pool.hpp"
#include "dataset/dataset.hpp"
#include "dataset/point_stream.hpp"
#include "recon/hole_fill.hpp"
#include "test_data.hpp"

namespace lidarscout::recon {
namespace {

struct Scene {
    std::vector<GroundSample> samples;
    std::vector<std::uint8_t> is_ground;  // the truth
};

// 200 x 200 m sloping 10 %, 4 samples per m2 with 3 cm of noise; a 30 x 20 m house 8 m high and
// twenty trees of 4 m crowns, 6-15 m high, on it.
Scene made_up_scene() {
    Scene s;
    std::mt19937 rng(7);
    std::uniform_real_distribution<double> pos(0.0, 200.0);
    std::normal_distribution<double> noise(0.0, 0.03);
    const auto ground_at = [](double x, double y) { return 100.0 + 0.1 * x + 0.02 * y; };
    std::vector<std::array<double, 3>> trees;
    for (int t = 0; t < 20; ++t) trees.push_back({20 + pos(rng) * 0.8, 20 + pos(rng) * 0.8, 6 + pos(rng) / 200 * 9});
    for (int k = 0; k < 160000; ++k) {
        const double x = pos(rng), y = pos(rng);
        double z = ground_at(x, y) + noise(rng);
        bool ground = true;
        if (x > 120 && x < 150 && y > 40 && y < 60) z += 8.0, ground = false;  // the roof
        for (const auto& [tx, ty, h] : trees) {
            if (ground && std::hypot(x - tx, y - ty) < 2.0 && k % 3 != 0) z += h, ground = false;  // a crown
        }
        s.samples.push_back({x, y, static_cast<float>(z)});
        s.is_ground.push_back(ground ? 1 : 0);
    }
    return s;
}

struct Errors {
    double type1 = 0, type2 = 0, total = 0;  // ground rejected, objects accepted, all wrong (fractions)
};

Errors errors_of(const std::vector<std::uint8_t>& truth, const std::vector<std::uint8_t>& found) {
    double ground = 0, objects = 0, rejected = 0, accepted = 0;
    for (std::size_t i = 0; i < truth.size(); ++i) {
        if (truth[i]) ++ground, rejected += found[i] ? 0 : 1;
        else ++objects, accepted += found[i] ? 1 : 0;
    }
    return {rejected / std::max(ground, 1.0), accepted / std::max(objects, 1.0),
            (rejected + accepted) / std::max(ground + objects, 1.0)};
}

TEST(GroundFilter, KeepsTheSlopeAndDropsTheHouseAndTheTrees) {
    const Scene s = made_up_scene();
    const GroundFilterParams p;
    const auto found = find_ground(s.samples, ground_lattice(0, 0, 200, p), p);
    const Errors e = errors_of(s.is_ground, found);
    std::printf("made-up scene: type I %.2f %%, type II %.2f %%, total %.2f %%\n", 100 * e.type1, 100 * e.type2,
                100 * e.total);
    EXPECT_LT(e.type1, 0.01) << "the 10 % slope is ground";
    EXPECT_LT(e.type2, 0.01) << "the roof and the crowns are not";
}

TEST(GroundFilter, AnEmptyOrOffLatticeInputFindsNoGround) {
    const GroundFilterParams p;
    EXPECT_TRUE(find_ground({}, ground_lattice(0, 0, 10, p), p).empty());
    const std::vector<GroundSample> off{{-5, -5, 1.0f}, {50, 50, 1.0f}};
    EXPECT_EQ(find_ground(off, ground_lattice(0, 0, 10, p), p), (std::vector<std::uint8_t>{0, 0}));
}

TEST(GroundFilter, TheLatticeGrowsItsCellsToStayWithinItsSize) {
    const GroundFilterParams p;
    EXPECT_EQ(ground_lattice(0, 0, 512, p).cells, 512);
    const GroundLattice wide = ground_lattice(0, 0, 5120, p, 2048);
    EXPECT_EQ(wide.cells, 2048);
    EXPECT_DOUBLE_EQ(wide.cell_m, 2.5);
}

TEST(GroundFilter, ItsReachIsTheLargestOpeningAndTwoCells) {
    GroundFilterParams p;  // an 18 m window
    EXPECT_EQ(opening_radius_cells(p, 1.0), 18);
    EXPECT_DOUBLE_EQ(ground_filter_reach_m(p, 1.0), 38.0);   // 2 x 18 + 2 cells of 1 m
    EXPECT_EQ(opening_radius_cells(p, 2.5), 8);              // whole cells: 7.2 rounded up
    EXPECT_DOUBLE_EQ(ground_filter_reach_m(p, 2.5), 45.0);  // 2 x 8 + 2 cells of 2.5 m
    p.window_m = 0.5;
    EXPECT_EQ(opening_radius_cells(p, 1.0), 1);  // at least one cell
}

TEST(GroundFilter, ParametersOutOfRangeAreRefused) {
    GroundFilterParams p;
    EXPECT_NO_THROW(check_ground_params(p));
    p.slope = -1;
    EXPECT_THROW(check_ground_params(p), Error);
    p.slope = 0;  // from the terrain
    EXPECT_NO_THROW(check_ground_params(p));
    p = {};
    p.window_m = std::nan("");
    EXPECT_THROW(check_ground_params(p), Error);
    p = {};
    p.window_m = 0.5;  // smaller than the cell
    EXPECT_THROW(check_ground_params(p), Error);
    p = {};
    p.threshold_m = -1;
    EXPECT_THROW(check_ground_params(p), Error);
}

// Every point but noise of a classified tile, in metres from its south-west corner; the survey's
// class 2 as the truth.
struct SurveyScene : Scene {
    double side = 0;
};

SurveyScene survey_scene(const std::string& file) {
    const auto ds = dataset::open_dataset({file});
    SurveyScene s;
    ThreadPool pool(2);
    double min_x = INFINITY, min_y = INFINITY, max_x = -INFINITY, max_y = -INFINITY, base = NAN;
    dataset::for_each_metric_batch(ds, 0, pool, [&](std::uint64_t, std::span<const dataset::MetricPoint> points) {
        for (const auto& p : points) {
            if (p.classification == 7 || p.classification == 18) continue;
            if (std::isnan(base)) base = p.z;
            s.samples.push_back({p.x, p.y, static_cast<float>(p.z - base)});
            s.is_ground.push_back(p.classification == 2 ? 1 : 0);
            min_x = std::min(min_x, p.x), min_y = std::min(min_y, p.y);
            max_x = std::max(max_x, p.x), max_y = std::max(max_y, p.y);
        }
    });
    for (auto& p : s.samples) p.x -= min_x, p.y -= min_y;
    s.side = std::max(max_x - min_x, max_y - min_y) + 1e-6;
    return s;
}

// The 1 m cell of a sample (in metres from the corner) on a lattice of n x n.
std::size_t cell_of(const GroundSample& s, int n) {
    return static_cast<std::size_t>(s.y) * n + static_cast<std::size_t>(s.x);
}

// The mean height of the chosen samples per 1 m cell, holes filled: a plain DTM to compare by.
std::vector<float> cell_means(const SurveyScene& s, const std::vector<std::uint8_t>& chosen, int n) {
    std::vector<double> sum(static_cast<std::size_t>(n) * n, 0.0), count(sum.size(), 0.0);
    for (std::size_t i = 0; i < s.samples.size(); ++i) {
        if (!chosen[i]) continue;
        const std::size_t c = cell_of(s.samples[i], n);
        sum[c] += s.samples[i].z, count[c] += 1;
    }
    std::vector<float> z(sum.size(), NAN);
    for (std::size_t c = 0; c < z.size(); ++c) {
        if (count[c] > 0) z[c] = static_cast<float>(sum[c] / count[c]);
    }
    hole_fill(z, n, std::vector<bool>(z.size(), true));
    return z;
}

// The absolute differences, at the cells where the survey has ground, between the surface of the
// ground found and that of the survey's ground class: {median, 95th percentile}.
std::pair<float, float> surface_differences(const SurveyScene& s, const std::vector<std::uint8_t>& found) {
    const int n = static_cast<int>(s.side) + 1;
    const std::vector<float> truth = cell_means(s, s.is_ground, n), ours = cell_means(s, found, n);
    std::vector<std::uint8_t> has_ground(truth.size(), 0);
    for (std::size_t i = 0; i < s.samples.size(); ++i) {
        if (s.is_ground[i]) has_ground[cell_of(s.samples[i], n)] = 1;
    }
    std::vector<float> d;
    for (std::size_t c = 0; c < truth.size(); ++c) {
        if (has_ground[c]) d.push_back(std::abs(ours[c] - truth[c]));
    }
    if (d.empty()) return {NAN, NAN};
    std::sort(d.begin(), d.end());
    return {d[d.size() / 2], d[d.size() * 95 / 100]};
}

struct SurveyCase {
    const char* file;  // under the surveys folder
};

class GroundFilterOnSurveys : public ::testing::TestWithParam<SurveyCase> {};

// Point by point the survey's ground class is a stricter truth than a DTM needs (some surveys
// leave low points within centimetres of the ground unclassified), so the check is the surface:
// the ground found must make the survey's ground surface where it has ground, within 15
// centimetres at the median and half a metre at the 95th percentile; type I errors (its ground
// rejected) must be rare.
TEST_P(GroundFilterOnSurveys, MakesTheSurfaceOfTheSurveysOwnGroundClass) {
    const SurveyScene s = survey_scene((test::surveys_dir() / GetParam().file).string());
    ASSERT_GT(s.samples.size(), 1000u);
    const GroundFilterParams p;
    const auto found = find_ground(s.samples, ground_lattice(0, 0, s.side, p), p);
    const Errors e = errors_of(s.is_ground, found);
    const auto [median, p95] = surface_differences(s, found);
    std::printf("%s (%zu points): type I %.2f %%, type II %.2f %%, total %.2f %%; surface |difference| median "
                "%.3f m, 95th percentile %.3f m\n", GetParam().file, s.samples.size(), 100 * e.type1,
                100 * e.type2, 100 * e.total, median, p95);
    EXPECT_LT(e.type1, 0.05);
    EXPECT_LT(median, 0.15f);
    EXPECT_LT(p95, 0.50f);
}

INSTANTIATE_TEST_SUITE_P(Classified, GroundFilterOnSurveys,
                         ::testing::Values(SurveyCase{"ky-woodford-county/5205000_3900000.laz"},
                                           SurveyCase{"lasr-bcts-strips/bcts_1.laz"},
                                           SurveyCase{"ign-lidar-hd-1km/test_semis_2023_0292_6833_LA93_IGN69.laz"},
                                           SurveyCase{"ign-lidar-hd-1km/Semis_2022_0906_6665_LA93_IGN69_ok.laz"},
                                           SurveyCase{"ign-lidar-hd-1km/test_semis_2021_0382_6565_LA93_IGN69.laz"}),
                         [](const auto& info) { return "Survey" + std::to_string(info.index); });

}  // namespace
}  // namespace lidarscout::recon
