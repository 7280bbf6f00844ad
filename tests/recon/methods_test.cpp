// The methods by name: names, shared-geometry runs equal single runs, marked patches, byte
// determinism and order independence, and all methods on real chunk points of a survey.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <random>

#include "core/error.hpp"
#include "dataset/chunk_points.hpp"
#include "dataset/las_colour.hpp"
#include "dataset/tile.hpp"
#include "io/file.hpp"
#include "recon/methods.hpp"
#include "recon_test_util.hpp"
#include "test_data.hpp"

namespace lidarscout::recon {
namespace {

TEST(ReconMethods, Names) {
    for (const Method m : kAllMethods) EXPECT_EQ(method_from_name(method_name(m)), m);
    EXPECT_EQ(method_name(Method::Splat), "splat");
    EXPECT_THROW(method_from_name("bicubic"), Error);
}

TEST(ReconMethods, SharedRunEqualsSingleRunsAndIsDeterministic) {
    auto points = test::random_window(370, 12, test::terrain);
    const PatchPoints patch = test::make_patch(points);
    const auto all = reconstruct(patch, kAllMethods);
    ASSERT_EQ(all.size(), kAllMethods.size());
    // Input order does not matter.
    std::mt19937_64 rng(1);
    std::shuffle(points.begin(), points.end(), rng);
    const PatchPoints shuffled = test::make_patch(points);
    for (std::size_t i = 0; i < all.size(); ++i) {
        const Reconstruction single = reconstruct(patch, kAllMethods[i]);
        EXPECT_EQ(all[i].method, kAllMethods[i]);
        EXPECT_EQ(all[i].status, PatchStatus::Ok);
        EXPECT_TRUE(test::same_bytes(all[i].height, single.height)) << method_name(kAllMethods[i]);
        EXPECT_TRUE(test::same_bytes(all[i].rgb, single.rgb)) << method_name(kAllMethods[i]);
        const Reconstruction other = reconstruct(shuffled, kAllMethods[i]);
        EXPECT_TRUE(test::same_bytes(all[i].height, other.height)) << method_name(kAllMethods[i]);
        EXPECT_TRUE(test::same_bytes(all[i].rgb, other.rgb)) << method_name(kAllMethods[i]);
        EXPECT_EQ(all[i].height.size, 96);
        EXPECT_EQ(all[i].rgb.channels, 3);
        for (const float v : all[i].height.values) EXPECT_TRUE(std::isfinite(v)) << method_name(kAllMethods[i]);
    }
}

TEST(ReconMethods, TooFewPointsMarkedForEveryMethod) {
    const PatchPoints patch = test::make_patch(test::random_window(20, 5, test::terrain));
    for (const Method m : kAllMethods) {
        const Reconstruction r = reconstruct(patch, m);
        EXPECT_EQ(r.status, PatchStatus::TooFewPoints);
        EXPECT_TRUE(r.height.empty());
        EXPECT_TRUE(r.rgb.empty());
    }
}

// Chunk points of the nine eastern Kentucky tiles (US survey feet -> metres) in a patch grid.
struct SurveyGrid {
    lidarscout::PatchGrid grid{0.0, 0.0, 640.0};
    double min_z = INFINITY, max_z = -INFINITY;
};

void load_kentucky(SurveyGrid& s) {
    const auto dir = lidarscout::test::surveys_dir() / "ky-jmo335-eastern-kentucky";
    for (const auto& entry : std::filesystem::directory_iterator(dir)) {
        if (entry.path().extension() != ".laz") continue;
        const io::File file = io::File::open(entry.path().string());
        const dataset::Tile tile = dataset::read_tile(file);
        const double xy = tile.crs().horizontal_to_metres, z = tile.crs().z_to_metres();
        for (const auto& cp : dataset::read_chunk_points(file, tile)) {
            const auto& p = cp.point;
            s.grid.add(p.x * xy, p.y * xy, p.z * z, dataset::rgb8_from_las(p.rgb[0], p.rgb[1], p.rgb[2]),
                       p.intensity, p.classification, 0);
            s.min_z = std::min(s.min_z, p.z * z);
            s.max_z = std::max(s.max_z, p.z * z);
        }
    }
}

TEST(ReconMethods, RealChunkPoints) {
    SurveyGrid s;
    load_kentucky(s);
    ASSERT_GT(s.grid.size(), 200u);
    // The cell whose window holds the most chunk points.
    lidarscout::CellKey best{};
    std::size_t most = 0;
    for (const auto cell : s.grid.cells()) {
        const std::size_t n = s.grid.window(cell, 160.0).size();
        if (n > most) {
            most = n;
            best = cell;
        }
    }
    const PatchPoints patch = make_patch_points(s.grid, best);
    ASSERT_EQ(patch.status, PatchStatus::Ok) << most << " chunk points";
    EXPECT_GE(patch.points.size(), 40u);
    EXPECT_GE(patch.centre_z, s.min_z);
    EXPECT_LE(patch.centre_z, s.max_z);
    const double range = s.max_z - s.min_z;
    for (const Reconstruction& r : reconstruct(patch, kAllMethods)) {
        const auto name = method_name(r.method);
        ASSERT_EQ(r.status, PatchStatus::Ok) << name;
        const Image crop = crop_centre(r.height, 64);
        std::size_t finite = 0;
        for (const float h : crop.values) {
            // Splatting leaves texels farther than 16 texels from every point empty (NaN).
            if (r.method == Method::Splat && std::isnan(h)) continue;
            ASSERT_TRUE(std::isfinite(h)) << name;
            ++finite;
            const double z = patch.to_metres(h);
            EXPECT_GT(z, s.min_z - 0.25 * range) << name;
            EXPECT_LT(z, s.max_z + 0.25 * range) << name;
        }
        EXPECT_GT(finite, crop.values.size() / 2) << name;
        const Image rgb = crop_centre(r.rgb, 64);
        const float slack = r.method == Method::Cubic ? 0.25f : 1e-6f;
        for (const float c : rgb.values) {
            if (r.method == Method::Splat && std::isnan(c)) continue;
            ASSERT_TRUE(std::isfinite(c)) << name;
            EXPECT_GE(c, -slack) << name;
            EXPECT_LE(c, 1.0f + slack) << name;
        }
    }
}

}  // namespace
}  // namespace lidarscout::recon
