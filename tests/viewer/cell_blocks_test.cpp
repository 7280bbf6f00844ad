// Cell blocks' chunk points (viewer/cell_blocks.hpp): a block's cells read from the grid into one set about the
// block's corner, each point where the grid has it, cells without points left out; and a copy of it without the
// cells a heightmap shows.
#include "viewer/cell_blocks.hpp"

#include <gtest/gtest.h>

#include <vector>

namespace lidarscout::viewer {
namespace {

constexpr double kOx = 700'000.0, kOy = 3'000'000.0;

TEST(ViewerCellBlocks, ABlocksChunkPointsAreItsCellsAboutItsCorner) {
    lidarscout::PatchGrid grid(kOx, kOy);
    // Block (1, 0) holds cells 16..31 x 0..15; its corner is cell (16, 0)'s.
    const CellKey a{17, 2}, b{30, 15}, empty{20, 5};
    grid.add(grid.cell_min_x(a) + 1, grid.cell_min_y(a) + 2, 101, {1, 2, 3}, 7, 2, 4);
    grid.add(grid.cell_min_x(a) + 3, grid.cell_min_y(a) + 4, 102, {}, 8, 2, 4);
    grid.add(grid.cell_min_x(b) + 639, grid.cell_min_y(b) + 639, 103, {}, 9, 6, 5);
    ASSERT_EQ(CellBlocks::key_of_cell(a), (CellKey{1, 0}));
    ASSERT_EQ(CellBlocks::key_of_cell(b), (CellKey{1, 0}));
    const std::vector<CellKey> cells{a, empty, b};
    const auto chunks = read_block_chunks(grid, {1, 0}, cells);
    EXPECT_DOUBLE_EQ(chunks->set.origin_x, kOx + 16 * 640.0);
    EXPECT_DOUBLE_EQ(chunks->set.origin_y, kOy);
    EXPECT_EQ(chunks->cells, (std::vector<CellKey>{a, b}));  // the empty cell left out
    EXPECT_EQ(chunks->ends, (std::vector<std::uint32_t>{2, 3}));
    ASSERT_EQ(chunks->set.points.size(), 3u);
    const auto at = [&](std::size_t i) {
        const auto& p = chunks->set.points[i];
        return std::vector<double>{chunks->set.origin_x + p.dx, chunks->set.origin_y + p.dy, p.dz};
    };
    const auto near = [](const std::vector<double>& got, const std::vector<double>& want) {
        for (std::size_t k = 0; k < 3; ++k) EXPECT_NEAR(got[k], want[k], 2e-3) << k;
    };
    near(at(0), {grid.cell_min_x(a) + 1, grid.cell_min_y(a) + 2, 101});
    near(at(1), {grid.cell_min_x(a) + 3, grid.cell_min_y(a) + 4, 102});
    near(at(2), {grid.cell_min_x(b) + 639, grid.cell_min_y(b) + 639, 103});
    EXPECT_EQ(chunks->set.points[0].r, 1);
    EXPECT_EQ(chunks->set.points[2].intensity, 9);
    EXPECT_EQ(chunks->set.points[2].classification, 6);
    EXPECT_NE(chunks->set.cache_key, 0u);
    EXPECT_GE(chunks->bytes(), 3 * sizeof(render::PointAttr));

    const PointSet without_a = chunks_without(*chunks, [&](CellKey c) { return c == a; });
    ASSERT_EQ(without_a.points.size(), 1u);
    EXPECT_EQ(without_a.points[0].intensity, 9);
    EXPECT_DOUBLE_EQ(without_a.origin_x, chunks->set.origin_x);
    EXPECT_NE(without_a.cache_key, chunks->set.cache_key);
    const PointSet without_b = chunks_without(*chunks, [&](CellKey c) { return c == b; });
    ASSERT_EQ(without_b.points.size(), 2u);
    EXPECT_EQ(without_b.points[1].intensity, 8);
    EXPECT_TRUE(chunks_without(*chunks, [](CellKey) { return true; }).points.empty());
}

}  // namespace
}  // namespace lidarscout::viewer
