// A count quadtree: an implicit quadtree over a grid of leaf cells, each node holding how many
// items its leaves hold, so that the items a viewer needs are found without visiting them all:
//   - visit(): every non-empty leaf whose rectangle a conservative test keeps (a frustum test of
//     the node's box: a rejected node is skipped whole), so work follows what is in view;
//   - nearest(): the non-empty leaf of least cost, best first over nodes whose cost is a lower
//     bound of their leaves' (a distance to the node's rectangle), so finding the next job near
//     the camera costs a few nodes per level, not a scan of every job.
// Items themselves live with the caller (leaf index -> its own lists); counts change with add().
// visits() counts the nodes examined, for tests that check work is bounded by what is in view.
// Not thread-safe: its owner locks.
#pragma once

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <optional>
#include <queue>
#include <utility>
#include <vector>

namespace lidarscout {

// Leaves [x0, x1) x [y0, y1) of the grid.
struct LeafRect {
    int x0 = 0, y0 = 0, x1 = 0, y1 = 0;
};

class CountQuadtree {
public:
    CountQuadtree() : CountQuadtree(1, 1) {}
    // A grid of nx x ny leaves (each at least 1), all counts 0.
    CountQuadtree(int nx, int ny) : nx_(std::max(nx, 1)), ny_(std::max(ny, 1)) {
        while ((1 << levels_) < std::max(nx_, ny_)) ++levels_;
        counts_.resize(levels_ + 1);
        for (int l = 0; l <= levels_; ++l) counts_[l].assign(std::size_t{1} << (2 * l), 0);
    }

    int width() const { return nx_; }
    int height() const { return ny_; }
    std::int64_t total() const { return counts_[0][0]; }
    std::int64_t count(int x, int y) const { return counts_[levels_][index(levels_, x, y)]; }

    // Adds `delta` to leaf (x, y) and every node above it.
    void add(int x, int y, std::int64_t delta) {
        for (int l = levels_, lx = x, ly = y; l >= 0; --l, lx >>= 1, ly >>= 1)
            counts_[l][index(l, lx, ly)] += static_cast<std::int32_t>(delta);
    }

    // Calls fn(x, y) for every leaf with a count whose rectangle, and every ancestor's, passes
    // keep(LeafRect) (keep must hold for a node whenever it holds for one of its leaves).
    template <class Keep, class Fn>
    void visit(Keep&& keep, Fn&& fn) const {
        visit_node(0, 0, 0, keep, fn);
    }

    // The leaf with a count of least exact(x, y), best first over nodes whose bound(LeafRect) is at
    // most any of their leaves' exact cost; a leaf's exact cost is asked only when its bound comes
    // first (a leaf may hold many items). nullopt when every count is 0.
    template <class Bound, class Exact>
    std::optional<std::pair<int, int>> nearest(Bound&& bound, Exact&& exact) const {
        std::optional<std::pair<int, int>> found;  // (each leaf an item: its row-major index)
        nearest_items(
            bound, [&](int x, int y, auto& add) { add(exact(x, y), static_cast<std::uint32_t>(y) * nx_ + x); },
            [](auto&) {},
            [&](std::uint32_t leaf) {
                found = std::pair{static_cast<int>(leaf % nx_), static_cast<int>(leaf / nx_)};
                return false;
            });
        return found;
    }

    // The items of the leaves with a count, least cost first, for as long as take(item) returns true: a
    // leaf's items are listed (items(x, y, add): add(cost, item) for each) when its bound comes first, and
    // each item comes out when its cost does (ties: the lower item; a node is opened before an item of its
    // bound's cost). `seed(add)` adds items that lie in no leaf. Finding k items near a point costs one
    // search, not k: each search first passes every leaf nearer than the nearest item (a loader's ring of
    // tiles done).
    template <class Bound, class Items, class Seed, class Take>
    void nearest_items(Bound&& bound, Items&& items, Seed&& seed, Take&& take) const {
        struct Node {
            double cost;
            bool item;
            std::uint32_t id;  // an item's, or a node's level
            int x, y;
            bool operator>(const Node& o) const {
                if (cost != o.cost) return cost > o.cost;
                if (item != o.item) return item;
                return id > o.id;
            }
        };
        std::priority_queue<Node, std::vector<Node>, std::greater<>> open;
        const auto add = [&](double cost, std::uint32_t item) { open.push({cost, true, item, 0, 0}); };
        seed(add);
        if (total() > 0) open.push({bound(rect(0, 0, 0)), false, 0, 0, 0});
        while (!open.empty()) {
            const Node n = open.top();
            open.pop();
            ++visits_;
            if (n.item) {
                if (!take(n.id)) return;
                continue;
            }
            const int level = static_cast<int>(n.id);
            if (level == levels_) {
                items(n.x, n.y, add);
                continue;
            }
            for (int c = 0; c < 4; ++c) {
                const int l = level + 1, x = 2 * n.x + (c & 1), y = 2 * n.y + (c >> 1);
                if (!inside(l, x, y) || counts_[l][index(l, x, y)] <= 0) continue;
                open.push({bound(rect(l, x, y)), false, static_cast<std::uint32_t>(l), x, y});
            }
        }
    }

    // The same with the cost of a leaf its rectangle's.
    template <class Cost>
    std::optional<std::pair<int, int>> nearest(Cost&& cost) const {
        return nearest(cost, [&](int x, int y) { return cost(LeafRect{x, y, x + 1, y + 1}); });
    }

    std::uint64_t visits() const { return visits_; }

private:
    std::size_t index(int level, int x, int y) const {
        return (static_cast<std::size_t>(y) << level) + static_cast<std::size_t>(x);
    }
    // The leaves node (x, y) of `level` covers, clipped to the grid.
    LeafRect rect(int level, int x, int y) const {
        const int s = levels_ - level;
        return {x << s, y << s, std::min((x + 1) << s, nx_), std::min((y + 1) << s, ny_)};
    }
    bool inside(int level, int x, int y) const {
        const int s = levels_ - level;
        return (x << s) < nx_ && (y << s) < ny_;
    }

    template <class Keep, class Fn>
    void visit_node(int level, int x, int y, Keep& keep, Fn& fn) const {
        ++visits_;
        if (counts_[level][index(level, x, y)] <= 0 || !keep(rect(level, x, y))) return;
        if (level == levels_) return fn(x, y);
        for (int c = 0; c < 4; ++c) {
            const int cx = 2 * x + (c & 1), cy = 2 * y + (c >> 1);
            if (inside(level + 1, cx, cy)) visit_node(level + 1, cx, cy, keep, fn);
        }
    }

    int nx_, ny_, levels_ = 0;
    std::vector<std::vector<std::int32_t>> counts_;  // per level, (2^level)^2 nodes, row-major
    mutable std::uint64_t visits_ = 0;
};

}  // namespace lidarscout
