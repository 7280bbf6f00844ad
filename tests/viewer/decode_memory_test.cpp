// Decode memory on real tiles: the bytes per point cover the records and the converted points;
// the largest unit is the largest LAZ chunk; a smaller piece holds less; the fitting plan fits
// its room and halves its pieces until it does; no plan when one chunk per thread does not fit.
#include "viewer/decode_memory.hpp"

#include <gtest/gtest.h>

#include "dataset/dataset.hpp"
#include "render/point_batch.hpp"
#include "survey_tiles.hpp"
#include "test_data.hpp"

namespace lidarscout::viewer {
namespace {

dataset::Dataset jmo335() {
    return dataset::open_dataset({(test::surveys_dir() / "ky-jmo335-eastern-kentucky").string()});
}

TEST(ViewerDecodeMemory, APieceHoldsItsRecordsAndPointsAndHalvesToFit) {
    const auto ds = jmo335();
    const auto& t = ds.tiles[survey::tile_named(ds, "N118E380")];
    ASSERT_TRUE(t.tile.chunks() && !t.tile.chunks()->empty());
    EXPECT_GE(piece_bytes_per_point(t), t.tile.header.record_length + sizeof(render::PointAttr));
    std::uint64_t largest = 0;
    for (const auto& c : *t.tile.chunks()) largest = std::max(largest, c.point_count);
    EXPECT_EQ(largest_unit_points(t), largest);

    const std::uint64_t n = t.tile.header.point_count;
    const auto big = decode_plan(t, n, 2, 1u << 18), small = decode_plan(t, n, 2, 1);
    EXPECT_LT(small.transient, big.transient);
    EXPECT_EQ(small.transient, 2 * largest * piece_bytes_per_point(t));  // one chunk per thread
    EXPECT_EQ(decode_plan(t, n, 1, 1).transient, small.transient / 2);

    const auto fit = fitting_decode_plan(t, n, 2, 1u << 18, big.transient / 3);
    ASSERT_TRUE(fit);
    EXPECT_LE(fit->transient, big.transient / 3);
    EXPECT_LT(fit->piece_points, 1u << 18);
    EXPECT_EQ(fitting_decode_plan(t, n, 2, 1u << 18, big.transient)->piece_points, 1u << 18);
    EXPECT_FALSE(fitting_decode_plan(t, n, 2, 1u << 18, small.transient - 1));
}

}  // namespace
}  // namespace lidarscout::viewer
