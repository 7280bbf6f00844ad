// The count quadtree: nearest() finds the leaf a scan of every leaf finds, visit() the leaves a
// rectangle test keeps, both after counts went up and down, on grids that are not powers of two;
// and their work follows what they return, not the grid's size.
#include "core/count_quadtree.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>
#include <set>

namespace lidarscout {
namespace {

// Distance from (px, py) to the rectangle of leaves r (leaf (x, y) = [x, x + 1) x [y, y + 1)).
double distance(const LeafRect& r, double px, double py) {
    const double dx = std::max({r.x0 - px, 0.0, px - r.x1});
    const double dy = std::max({r.y0 - py, 0.0, py - r.y1});
    return std::hypot(dx, dy);
}

TEST(CountQuadtree, NearestAndVisitMatchAScanOfEveryLeaf) {
    std::mt19937 rng(3);
    for (const auto [nx, ny] : {std::pair{1, 1}, {5, 3}, {37, 61}, {64, 64}}) {
        CountQuadtree tree(nx, ny);
        std::vector<int> counts(static_cast<std::size_t>(nx) * ny, 0);
        std::uniform_int_distribution<int> x_of(0, nx - 1), y_of(0, ny - 1);
        for (int i = 0; i < nx * ny / 3 + 1; ++i) {
            const int x = x_of(rng), y = y_of(rng);
            tree.add(x, y, 2);
            counts[static_cast<std::size_t>(y) * nx + x] += 2;
        }
        for (int i = 0; i < nx * ny / 6; ++i) {  // some go back to 0
            const int x = x_of(rng), y = y_of(rng);
            int& c = counts[static_cast<std::size_t>(y) * nx + x];
            if (c == 0) continue;
            tree.add(x, y, -c);
            c = 0;
        }
        std::uniform_real_distribution<double> px(-5, nx + 5), py(-5, ny + 5);
        for (int q = 0; q < 50; ++q) {
            const double x = px(rng), y = py(rng);
            double best = std::numeric_limits<double>::infinity();
            for (int j = 0; j < ny; ++j)
                for (int i = 0; i < nx; ++i)
                    if (counts[static_cast<std::size_t>(j) * nx + i] > 0)
                        best = std::min(best, distance({i, j, i + 1, j + 1}, x, y));
            const auto leaf = tree.nearest([&](const LeafRect& r) { return distance(r, x, y); });
            if (std::isinf(best)) {
                EXPECT_FALSE(leaf);
                continue;
            }
            ASSERT_TRUE(leaf);
            EXPECT_GT(tree.count(leaf->first, leaf->second), 0);
            EXPECT_DOUBLE_EQ(distance({leaf->first, leaf->second, leaf->first + 1, leaf->second + 1}, x, y), best);

            // The leaves within 4 of (x, y): visit() keeps those a scan keeps.
            const auto near = [&](const LeafRect& r) { return distance(r, x, y) <= 4; };
            std::set<std::pair<int, int>> seen, expected;
            tree.visit(near, [&](int i, int j) { seen.emplace(i, j); });
            for (int j = 0; j < ny; ++j)
                for (int i = 0; i < nx; ++i)
                    if (counts[static_cast<std::size_t>(j) * nx + i] > 0 && near({i, j, i + 1, j + 1}))
                        expected.emplace(i, j);
            EXPECT_EQ(seen, expected);
        }
    }
}

// On a 1024 x 1024 grid with every leaf counted, the nearest leaf costs a few nodes per level and
// a small window's visit the nodes around it: neither looks at the million leaves.
TEST(CountQuadtree, WorkFollowsTheAnswerNotTheGrid) {
    CountQuadtree tree(1024, 1024);
    for (int y = 0; y < 1024; ++y)
        for (int x = 0; x < 1024; ++x) tree.add(x, y, 1);
    std::uint64_t before = tree.visits();
    const auto leaf = tree.nearest([](const LeafRect& r) { return distance(r, 500.5, 700.5); });
    ASSERT_TRUE(leaf);
    EXPECT_EQ(*leaf, (std::pair{500, 700}));
    EXPECT_LE(tree.visits() - before, 4u * 11);  // levels 0..10
    before = tree.visits();
    int leaves = 0;
    tree.visit([](const LeafRect& r) { return distance(r, 100.5, 100.5) <= 2; }, [&](int, int) { ++leaves; });
    EXPECT_EQ(leaves, 21);  // the leaves whose square is within 2 of a leaf centre
    EXPECT_LE(tree.visits() - before, 4u * 11 * 9);
    EXPECT_EQ(tree.total(), 1024 * 1024);
}

}  // namespace
}  // namespace lidarscout
