// find_crossing: the edges in a grid of cells (sorted by cell), pairs of a part's edges sharing a cell
// tested for a proper crossing, the work counted against a cap set by the vertex count.
#include "core/polygon_validity.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <vector>

namespace lidarscout {
namespace {

// The side of c seen from a -> b: +1 left, -1 right, 0 on the line.
int side(const XY& a, const XY& b, const XY& c) {
    const double v = (b.x - a.x) * (c.y - a.y) - (b.y - a.y) * (c.x - a.x);
    return (v > 0) - (v < 0);
}

// Whether a-b and c-d cross: each has the other's ends strictly on both sides.
bool cross(const XY& a, const XY& b, const XY& c, const XY& d) {
    return side(a, b, c) * side(a, b, d) < 0 && side(c, d, a) * side(c, d, b) < 0;
}

XY crossing_point(const XY& a, const XY& b, const XY& c, const XY& d) {
    const double rx = b.x - a.x, ry = b.y - a.y, sx = d.x - c.x, sy = d.y - c.y;
    const double t = ((c.x - a.x) * sy - (c.y - a.y) * sx) / (rx * sy - ry * sx);
    return {a.x + t * rx, a.y + t * ry};
}

// The polygon's edges numbered in ring order: edge e of ring r is vertex e - first[r] of that ring to the
// next (the last back to the first).
class Edges {
public:
    explicit Edges(const MultiPolygon& p) : polygon_(p) {
        for (std::size_t r = 0; r < p.ring_count(); ++r) {
            first_.push_back(static_cast<std::uint32_t>(ring_of_.size()));
            ring_of_.insert(ring_of_.end(), p.ring(r).size(), static_cast<std::uint32_t>(r));
        }
    }
    std::size_t size() const { return ring_of_.size(); }
    std::size_t ring(std::size_t e) const { return ring_of_[e]; }
    std::size_t index(std::size_t e) const { return e - first_[ring_of_[e]]; }
    std::pair<XY, XY> ends(std::size_t e) const {
        const auto v = polygon_.ring(ring_of_[e]);
        const std::size_t k = index(e);
        return {v[k], v[(k + 1) % v.size()]};
    }

private:
    const MultiPolygon& polygon_;
    std::vector<std::uint32_t> first_, ring_of_;
};

struct Entry {
    std::uint64_t cell;
    std::uint32_t edge;
    bool operator<(const Entry& o) const { return cell < o.cell || (cell == o.cell && edge < o.edge); }
};

// A square grid over the polygon's box, its cells twice the mean edge long (at most 2^26 a side).
struct Grid {
    double x0, y0, cell;
    std::uint64_t columns;

    Grid(const MultiPolygon& p, const Edges& edges) : x0(p.min_x()), y0(p.min_y()) {
        double length = 0;
        for (std::size_t e = 0; e < edges.size(); ++e) {
            const auto [a, b] = edges.ends(e);
            length += std::hypot(b.x - a.x, b.y - a.y);
        }
        const double extent = std::max(p.max_x() - x0, p.max_y() - y0);
        cell = std::max(2 * length / static_cast<double>(std::max<std::size_t>(edges.size(), 1)), extent / (1 << 26));
        if (!(cell > 0) || !std::isfinite(cell)) cell = 1;
        columns = column(p.max_x()) + 1;
    }
    std::uint64_t column(double x) const { return static_cast<std::uint64_t>(std::max(0.0, (x - x0) / cell)); }
    std::uint64_t row(double y) const { return static_cast<std::uint64_t>(std::max(0.0, (y - y0) / cell)); }

    // Calls fn(cell) for the cells the segment a-b may pass, column by column (a hair wider, so that
    // rounding never leaves out the cell where it crosses another).
    template <typename Fn>
    void cells_of(const XY& a, const XY& b, Fn&& fn) const {
        const double hair = cell * 1e-9;
        const double lo_x = std::min(a.x, b.x), hi_x = std::max(a.x, b.x);
        const auto y_at = [&](double x) { return a.x == b.x ? a.y : a.y + (b.y - a.y) * (x - a.x) / (b.x - a.x); };
        for (std::uint64_t c = column(lo_x - hair), last = column(hi_x + hair); c <= last; ++c) {
            const double xa = std::max(lo_x, x0 + static_cast<double>(c) * cell);
            const double xb = std::min(hi_x, x0 + static_cast<double>(c + 1) * cell);
            double ya = y_at(xa), yb = y_at(xb);
            if (a.x == b.x) ya = a.y, yb = b.y;
            const auto [lo, hi] = std::minmax(ya, yb);
            for (std::uint64_t r = row(lo - hair), top = row(hi + hair); r <= top; ++r) fn(r * columns + c);
        }
    }
};

// Records the crossing of edges e < f when it comes before the one found so far.
void note_crossing(const MultiPolygon& p, const Edges& edges, std::size_t e, std::size_t f, CrossingCheck& out,
                   std::pair<std::size_t, std::size_t>& best) {
    if (out.first && std::pair{e, f} >= best) return;
    const auto [a, b] = edges.ends(e);
    const auto [c, d] = edges.ends(f);
    if (!cross(a, b, c, d)) return;
    best = {e, f};
    const std::size_t part = p.polygon_of_ring(edges.ring(e));
    const std::size_t outer = p.first_ring_of_polygon(part);
    out.first = PolygonCrossing{part,           edges.ring(e) - outer, edges.index(e), edges.ring(f) - outer,
                                edges.index(f), crossing_point(a, b, c, d)};
}

}  // namespace

CrossingCheck find_crossing(const MultiPolygon& p) {
    CrossingCheck out;
    out.parts = p.polygon_count();
    const Edges edges(p);
    out.cap = 48 * static_cast<std::uint64_t>(edges.size()) + 1'000'000;
    const Grid grid(p, edges);
    std::vector<Entry> entries;
    for (std::size_t e = 0; e < edges.size() && out.checked; ++e) {
        const auto [a, b] = edges.ends(e);
        grid.cells_of(a, b, [&](std::uint64_t cell) {
            if (++out.work > out.cap) return void(out.checked = false);
            if (out.checked) entries.push_back({cell, static_cast<std::uint32_t>(e)});
        });
    }
    if (!out.checked) return out;
    std::sort(entries.begin(), entries.end());
    std::pair<std::size_t, std::size_t> best;
    for (std::size_t i = 0; i < entries.size() && out.checked;) {
        std::size_t end = i;
        while (end < entries.size() && entries[end].cell == entries[i].cell) ++end;
        for (std::size_t j = i; j < end && out.checked; ++j) {
            const std::size_t e = entries[j].edge, part = p.polygon_of_ring(edges.ring(e));
            for (std::size_t k = j + 1; k < end; ++k) {
                if (++out.work > out.cap) {
                    out.checked = false;
                    break;
                }
                const std::size_t f = entries[k].edge;
                if (p.polygon_of_ring(edges.ring(f)) == part) note_crossing(p, edges, e, f, out, best);
            }
        }
        i = end;
    }
    return out;
}

namespace {

std::string ring_name(std::size_t ring) { return ring == 0 ? "outer ring" : "hole " + std::to_string(ring); }

}  // namespace

std::string crossing_warning(const CrossingCheck& check, const std::string& name) {
    if (check.first) {
        const auto& c = *check.first;
        char at[96];
        std::snprintf(at, sizeof at, "(%.3f, %.3f)", c.at.x, c.at.y);
        const std::string part = check.parts > 1 ? "part " + std::to_string(c.part + 1) + ": " : "";
        return name + ": the polygon's edges cross at " + at + " (" + part + ring_name(c.ring_a) + " edge " +
               std::to_string(c.edge_a + 1) + " and " + ring_name(c.ring_b) + " edge " + std::to_string(c.edge_b + 1) +
               "); a point is inside where the rings enclose it an odd number of times (even-odd rule), which may "
               "not be the area meant";
    }
    if (check.checked) return {};
    return name + ": not checked for crossing edges (its edges lie too close together: the check stopped after " +
           std::to_string(check.cap) + " steps, its cap for this many vertices); a point is inside where the rings "
           "enclose it an odd number of times (even-odd rule)";
}

}  // namespace lidarscout
