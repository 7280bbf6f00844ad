// The patch grid: cell assignment at edges, window queries against a brute-force filter,
// concurrent adds, points added a cell at a time, precision far from the origin, and memory per point.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <random>
#include <span>
#include <thread>
#include <vector>

#include "core/error.hpp"
#include "core/patch_grid.hpp"

namespace lidarscout {
namespace {

constexpr double kSize = 640.0;

void add_simple(PatchGrid& grid, double x, double y, double z, std::uint32_t id) {
    grid.add(x, y, z, Rgb8{1, 2, 3}, 7, 2, id);
}

TEST(PatchGrid, PointIsCompact) {
    EXPECT_LE(sizeof(GridPoint), 32u);
    EXPECT_EQ(sizeof(GridPoint), 24u);
}

TEST(PatchGrid, CellAssignmentAtEdgesAndNegative) {
    const PatchGrid grid(0.0, 0.0, kSize);
    EXPECT_EQ(grid.cell_of(0.0, 0.0), (CellKey{0, 0}));
    EXPECT_EQ(grid.cell_of(640.0, 1280.0), (CellKey{1, 2}));  // an edge belongs to the upper cell
    EXPECT_EQ(grid.cell_of(639.999, 639.999), (CellKey{0, 0}));
    EXPECT_EQ(grid.cell_of(-0.001, -640.0), (CellKey{-1, -1}));
    EXPECT_EQ(grid.cell_of(-640.001, -1280.0), (CellKey{-2, -2}));

    const PatchGrid shifted(1000.5, -2000.25, kSize);
    EXPECT_EQ(shifted.cell_of(1000.5 + 640.0, -2000.25), (CellKey{1, 0}));
    EXPECT_EQ(shifted.cell_of(1000.0, -2000.5), (CellKey{-1, -1}));
}

TEST(PatchGrid, EdgePointStoredAtZeroOffset) {
    PatchGrid grid(1000.5, -2000.25, kSize);
    add_simple(grid, 1000.5 + 640.0, -2000.25 - 640.0, 5.0, 9);
    const auto points = grid.points_in({1, -1});
    ASSERT_EQ(points.size(), 1u);
    EXPECT_EQ(points[0].dx, 0.0f);
    EXPECT_EQ(points[0].dy, 0.0f);
    EXPECT_EQ(points[0].tile, 9u);
    EXPECT_TRUE(grid.points_in({0, 0}).empty());
    EXPECT_EQ(grid.cells(), (std::vector<CellKey>{{1, -1}}));
}

TEST(PatchGrid, RejectsBadArguments) {
    EXPECT_THROW(PatchGrid(0, 0, 0.0), Error);
    PatchGrid grid(0, 0, kSize);
    EXPECT_THROW(add_simple(grid, 1e15, 0, 0, 0), Error);
    EXPECT_THROW(add_simple(grid, std::nan(""), 0, 0, 0), Error);
    EXPECT_THROW(grid.window({0, 0}, -1.0), Error);
}

// Random points, none within 1 mm of a window edge (offsets 160 / 480 mod 640), so that the
// float offsets cannot flip a point across an edge; ids are the tile field.
struct RandomPoint {
    double x, y, z;
};

bool near_window_edge(double local) {
    const double m = local - std::floor(local / kSize) * kSize;
    for (const double edge : {0.0, 160.0, 480.0, 640.0}) {
        if (std::abs(m - edge) < 1e-3) return true;
    }
    return false;
}

std::vector<RandomPoint> random_points(double ox, double oy, std::size_t n) {
    std::mt19937_64 rng(12345);
    std::uniform_real_distribution<double> coord(-5 * kSize, 5 * kSize);
    std::uniform_real_distribution<double> height(-50.0, 3000.0);
    std::vector<RandomPoint> points;
    while (points.size() < n) {
        const double lx = coord(rng), ly = coord(rng);
        if (near_window_edge(lx) || near_window_edge(ly)) continue;
        points.push_back({ox + lx, oy + ly, height(rng)});
    }
    return points;
}

TEST(PatchGrid, WindowMatchesBruteForce) {
    const double ox = 512345.25, oy = 4123456.75;
    PatchGrid grid(ox, oy, kSize);
    const auto points = random_points(ox, oy, 20000);
    for (std::uint32_t i = 0; i < points.size(); ++i) add_simple(grid, points[i].x, points[i].y, points[i].z, i);
    ASSERT_EQ(grid.size(), points.size());

    for (const double padding : {160.0, 0.0, 700.0}) {
        for (int iy = -6; iy <= 5; ++iy) {
            for (int ix = -6; ix <= 5; ++ix) {
                const double x0 = ox + ix * kSize - padding, x1 = ox + (ix + 1) * kSize + padding;
                const double y0 = oy + iy * kSize - padding, y1 = oy + (iy + 1) * kSize + padding;
                std::vector<std::uint32_t> expected;
                for (std::uint32_t i = 0; i < points.size(); ++i) {
                    const auto& p = points[i];
                    if (p.x >= x0 && p.x < x1 && p.y >= y0 && p.y < y1) expected.push_back(i);
                }
                std::vector<std::uint32_t> got;
                for (const auto& p : grid.window({ix, iy}, padding)) {
                    got.push_back(p.tile);
                    const auto& src = points[p.tile];
                    EXPECT_NEAR(p.x, src.x, 1e-4);
                    EXPECT_NEAR(p.y, src.y, 1e-4);
                    EXPECT_NEAR(p.z, src.z, 1e-3);
                }
                std::sort(got.begin(), got.end());
                EXPECT_EQ(got, expected) << "cell " << ix << "," << iy << " padding " << padding;
            }
        }
    }
}

TEST(PatchGrid, ConcurrentAdds) {
    constexpr int kThreads = 4;
    constexpr std::uint32_t kPerThread = 100000;
    const double ox = -1234.5, oy = 98765.25;
    PatchGrid grid(ox, oy, kSize);
    const auto position = [&](std::uint32_t id) {
        return RandomPoint{ox + (id % 7919) * 1.37 - 3000.0, oy + (id % 104729) * 0.091 - 2000.0,
                           static_cast<double>(id % 1000)};
    };
    std::vector<std::thread> threads;
    for (int t = 0; t < kThreads; ++t) {
        threads.emplace_back([&, t] {
            for (std::uint32_t i = 0; i < kPerThread; ++i) {
                const std::uint32_t id = t * 1'000'000u + i;
                const auto p = position(id);
                grid.add(p.x, p.y, p.z, Rgb8{std::uint8_t(t), 0, 0}, std::uint16_t(i), 1, id);
            }
        });
    }
    for (auto& th : threads) th.join();

    ASSERT_EQ(grid.size(), std::size_t{kThreads} * kPerThread);
    std::vector<std::uint32_t> ids;
    for (const CellKey cell : grid.cells()) {
        for (const auto& gp : grid.points_in(cell)) {
            const auto p = grid.to_absolute(cell, gp);
            const auto want = position(p.tile);
            ASSERT_NEAR(p.x, want.x, 1e-4);
            ASSERT_NEAR(p.y, want.y, 1e-4);
            ASSERT_EQ(p.z, want.z);
            ASSERT_EQ(p.rgb.r, p.tile / 1'000'000u);
            ASSERT_EQ(p.intensity, std::uint16_t(p.tile % 1'000'000u));
            ids.push_back(p.tile);
        }
    }
    ASSERT_EQ(ids.size(), grid.size());
    std::sort(ids.begin(), ids.end());
    for (int t = 0; t < kThreads; ++t) {
        for (std::uint32_t i = 0; i < kPerThread; ++i) {
            ASSERT_EQ(ids[t * kPerThread + i], t * 1'000'000u + i);
        }
    }
}

TEST(PatchGrid, PrecisionFarFromOrigin) {
    const double ox = 300000.0, oy = 4000000.0;
    PatchGrid grid(ox, oy, kSize);
    const double x = ox + 500000.123, y = oy - 499999.877, z = 4321.987;
    add_simple(grid, x, y, z, 1);
    const CellKey cell = grid.cell_of(x, y);
    const auto points = grid.window(cell);
    ASSERT_EQ(points.size(), 1u);
    EXPECT_NEAR(points[0].x, x, 1e-3);
    EXPECT_NEAR(points[0].y, y, 1e-3);
    EXPECT_NEAR(points[0].z, z, 1e-3);
    EXPECT_LT(std::abs(points[0].x - x), 1e-4);  // float offset ulp <= 6.1e-5 m in a 640 m cell
}

// Points added a cell at a time (add_in_cells) land as add puts them, in order within each cell, and the running
// count of bytes and points stays the sum over the cells.
TEST(PatchGrid, PointsAddedACellAtATimeEqualThoseAddedOneByOne) {
    PatchGrid one(0, 0, kSize), runs(0, 0, kSize);
    std::mt19937 rng(11);
    std::uniform_real_distribution<double> coord(-3 * kSize, 3 * kSize);
    std::vector<std::pair<CellKey, GridPoint>> placed;
    for (std::uint32_t i = 0; i < 5000; ++i) {
        const double x = coord(rng), y = coord(rng), z = i * 0.5;
        one.add(x, y, z, Rgb8{1, 2, 3}, 7, 2, i);
        const CellKey cell = runs.cell_of(x, y);
        placed.emplace_back(cell, runs.point_in(cell, x, y, z, Rgb8{1, 2, 3}, 7, 2, i));
    }
    std::stable_sort(placed.begin(), placed.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
    runs.add_in_cells(std::span(placed).first(2500));
    runs.add_in_cells(std::span(placed).subspan(2500));
    ASSERT_EQ(runs.size(), one.size());
    ASSERT_EQ(runs.cells(), one.cells());
    for (const CellKey cell : one.cells()) {
        const auto a = one.points_in(cell), b = runs.points_in(cell);
        ASSERT_EQ(a.size(), b.size());
        for (std::size_t k = 0; k < a.size(); ++k) {
            EXPECT_EQ(a[k].tile, b[k].tile);
            EXPECT_EQ(a[k].dx, b[k].dx);
            EXPECT_EQ(a[k].z, b[k].z);
        }
    }
    EXPECT_EQ(runs.memory_bytes(), runs.counted_memory_bytes());
}

TEST(PatchGrid, MemoryPerPoint) {
    PatchGrid grid(0, 0, kSize);
    std::mt19937 rng(7);
    std::uniform_real_distribution<double> coord(0.0, 10 * kSize);
    constexpr std::size_t kPoints = 1'000'000;
    for (std::size_t i = 0; i < kPoints; ++i) add_simple(grid, coord(rng), coord(rng), 1.0, 0);
    const std::size_t cells = grid.cells().size();
    ASSERT_EQ(cells, 100u);

    const std::size_t before = grid.memory_bytes();
    EXPECT_EQ(before, grid.counted_memory_bytes());  // the running count is the sum over the cells
    grid.shrink_to_fit();
    const std::size_t after = grid.memory_bytes();
    EXPECT_EQ(after, grid.counted_memory_bytes());
    EXPECT_LT(after, before);
    EXPECT_GE(after, kPoints * sizeof(GridPoint));  // never under-reported
    // Stated overhead: per cell kCellOverheadBytes, plus the shards and their bucket arrays.
    const std::size_t fixed_bound = 64 * 1024;
    EXPECT_LE(after, kPoints * 32 + cells * PatchGrid::kCellOverheadBytes + fixed_bound);
    std::printf("PatchGrid memory: %zu B for %zu points in %zu cells = %.2f B/point "
                "(%.2f before shrink_to_fit), %zu B overhead per cell\n",
                after, kPoints, cells, double(after) / kPoints, double(before) / kPoints,
                PatchGrid::kCellOverheadBytes);
}

TEST(PatchGrid, PointsReadInPlaceAreThoseCopied) {
    PatchGrid grid(0, 0, 100);
    for (int i = 0; i < 50; ++i) grid.add(i * 7.5, i * 3.0, i, {1, 2, 3}, static_cast<std::uint16_t>(i), 2, i % 3);
    for (const CellKey cell : grid.cells()) {
        const auto copied = grid.points_in(cell);
        std::vector<GridPoint> read;
        grid.read_points(cell, [&](std::span<const GridPoint> p) { read.assign(p.begin(), p.end()); });
        ASSERT_FALSE(copied.empty());
        ASSERT_EQ(read.size(), copied.size());
        for (std::size_t k = 0; k < read.size(); ++k) {
            EXPECT_EQ(read[k].z, copied[k].z);
            EXPECT_EQ(read[k].tile, copied[k].tile);
        }
    }
    std::size_t seen = 1;
    grid.read_points({1000, 1000}, [&](std::span<const GridPoint> p) { seen = p.size(); });
    EXPECT_EQ(seen, 0u) << "a cell without points: an empty span";
}

}  // namespace
}  // namespace lidarscout
