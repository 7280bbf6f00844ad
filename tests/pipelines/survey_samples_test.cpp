// The one-pass sampler: chunk points are exactly every K-th point of each tile in file order,
// ground truth holds every point of the requested patches, the auto stride follows its rule,
// and candidate patches are deterministic for a seed and inside the data.
#include <gtest/gtest.h>

#include <cmath>

#include "core/thread_pool.hpp"
#include "dataset/dataset.hpp"
#include "dataset/point_reader.hpp"
#include "io/file.hpp"
#include "las/point_format.hpp"
#include "pipelines/survey_samples.hpp"
#include "test_data.hpp"

namespace lidarscout::pipelines {
namespace {

const dataset::Dataset& woodford() {
    static const auto ds = dataset::open_dataset({(test::surveys_dir() / "ky-woodford-county").string()});
    return ds;
}

TEST(SurveySamples, AutoStrideFollowsTheRule) {
    const auto& ds = woodford();
    const double d = point_density(ds);
    ASSERT_GT(d, 0.1);
    PatchSpec spec;
    EXPECT_EQ(auto_stride(ds, spec), static_cast<std::uint64_t>(std::round(d * 2500.0)));  // 960 m window
    spec.texel_m = 1.0;
    EXPECT_EQ(auto_stride(ds, spec), std::max<std::uint64_t>(1, std::llround(d * 96.0 * 96.0 / 368.64)));
}

TEST(SurveySamples, CandidatesAreDeterministicAndInsideTheData) {
    const auto& ds = woodford();
    const Lattice l = lattice_for(ds, PatchSpec{});
    const auto a = candidate_patches(ds, l, 50, 7), b = candidate_patches(ds, l, 50, 7),
               c = candidate_patches(ds, l, 50, 8);
    EXPECT_EQ(a, b);
    ASSERT_GT(a.size(), 1u);
    EXPECT_NE(a, c);  // another seed, another order
    for (const auto& cell : a) {
        const double x = l.origin_x + (cell.ix + 0.5) * 640.0, y = l.origin_y + (cell.iy + 0.5) * 640.0;
        EXPECT_LT(ds.bounds_m.distance_xy(x, y), 640.0);
    }
}

TEST(SurveySamples, OffsetLatticesShiftDiagonallyByFractionsOfAPatch) {
    const Lattice base = lattice_for(woodford(), PatchSpec{});
    const auto ls = offset_lattices(base, 4);
    ASSERT_EQ(ls.size(), 4u);
    for (int k = 0; k < 4; ++k) {
        EXPECT_DOUBLE_EQ(ls[k].origin_x, base.origin_x + 160.0 * k);
        EXPECT_DOUBLE_EQ(ls[k].origin_y, base.origin_y + 160.0 * k);
        EXPECT_EQ(ls[k].spec.texel_m, base.spec.texel_m);
    }
    // A shifted lattice still finds the survey's patches.
    EXPECT_FALSE(candidate_patches(woodford(), ls[2], 10, 1).empty());
}

TEST(SurveySamples, EveryKthPointAndAllPointsOfThePatches) {
    const auto& ds = woodford();
    ASSERT_EQ(ds.tiles.size(), 1u);
    const Lattice l = lattice_for(ds, PatchSpec{});
    const auto patches = candidate_patches(ds, l, 3, 1);
    constexpr std::uint64_t kStride = 997;
    ThreadPool pool(2);
    const auto s = sample_survey(ds, {{l, kStride, patches}}, pool);
    const auto& t = ds.tiles[0];
    EXPECT_EQ(s.points, t.tile.header.point_count);
    EXPECT_EQ(s.samples[0].chunk_points->size(), (t.tile.header.point_count + kStride - 1) / kStride);
    // Independent count of the ground-truth points of the first patch, and the first chunk point.
    const auto file = io::File::open(t.tile.path());
    const auto& fmt = las::point_format_info(t.tile.header.point_format);
    std::uint64_t in_patch = 0;
    double first_x = NAN;
    dataset::for_each_record_batch(file, t.tile, pool, [&](std::uint64_t first, std::span<const std::uint8_t> rec) {
        for (std::size_t k = 0; k < rec.size() / t.tile.header.record_length; ++k) {
            const auto p = las::decode_point(rec.subspan(k * t.tile.header.record_length), fmt, t.tile.header);
            if (first + k == 0) first_x = p.x * t.xy_to_metres;
            const auto cell = s.samples[0].chunk_points->cell_of(p.x * t.xy_to_metres, p.y * t.xy_to_metres);
            in_patch += cell == patches[0];
        }
    });
    ASSERT_GT(in_patch, 1000u);
    // covered texels <= points in the patch; and the patch's chunk points are ~ in_patch / K
    EXPECT_LE(s.samples[0].truth->covered_texels(0), in_patch);
    const auto in_cell = s.samples[0].chunk_points->points_in(patches[0]).size();
    EXPECT_NEAR(static_cast<double>(in_cell), in_patch / double(kStride), 3.0 + in_patch / double(kStride) * 0.2);
    bool found_first = false;
    for (const auto cell : s.samples[0].chunk_points->cells()) {
        for (const auto& p : s.samples[0].chunk_points->points_in(cell)) {
            found_first |= std::abs(s.samples[0].chunk_points->to_absolute(cell, p).x - first_x) < 1e-3;
        }
    }
    EXPECT_TRUE(found_first);  // point 0 is a chunk point
}

}  // namespace
}  // namespace lidarscout::pipelines
