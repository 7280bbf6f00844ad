// find_crossing: a Shamos-Hoey sweep of each part, its edges ordered along the sweep line by
// orientation tests (no intersection computed to order them), events in (x, y) order.
#include "core/polygon_validity.hpp"

#include <algorithm>
#include <cstdio>
#include <iterator>
#include <set>
#include <vector>

namespace lidarscout {
namespace {

// The side of c seen from a -> b: +1 left, -1 right, 0 on the line.
int side(const XY& a, const XY& b, const XY& c) {
    const double v = (b.x - a.x) * (c.y - a.y) - (b.y - a.y) * (c.x - a.x);
    return (v > 0) - (v < 0);
}

// The sweep's order of points: west to east, south to north on one meridian.
bool before(const XY& a, const XY& b) { return a.x < b.x || (a.x == b.x && a.y < b.y); }

// An edge of a part, its ends in sweep order.
struct Segment {
    XY l, r;
    std::uint32_t ring, edge;  // the ring in its part and the edge in its ring
};

// Whether a and b cross: each has the other's ends strictly on both sides.
bool cross(const Segment& a, const Segment& b) {
    return side(a.l, a.r, b.l) * side(a.l, a.r, b.r) < 0 && side(b.l, b.r, a.l) * side(b.l, b.r, a.r) < 0;
}

XY crossing_point(const Segment& a, const Segment& b) {
    const double rx = a.r.x - a.l.x, ry = a.r.y - a.l.y, sx = b.r.x - b.l.x, sy = b.r.y - b.l.y;
    const double t = ((b.l.x - a.l.x) * sy - (b.l.y - a.l.y) * sx) / (rx * sy - ry * sx);
    return {a.l.x + t * rx, a.l.y + t * ry};
}

// Where s lies against t, s starting no earlier than t (both on the sweep line): +1 above, -1 below,
// 0 along t's line.
int against(const Segment& s, const Segment& t) {
    const int at_start = side(t.l, t.r, s.l);
    return at_start != 0 ? at_start : side(t.l, t.r, s.r);
}

// The order along the sweep line, south to north (edges along one line by their number).
struct Below {
    const std::vector<Segment>* segments;
    bool operator()(std::uint32_t a, std::uint32_t b) const {
        if (a == b) return false;
        const Segment &s = (*segments)[a], &t = (*segments)[b];
        const int v = before(s.l, t.l) ? -against(t, s) : against(s, t);
        return v != 0 ? v < 0 : a < b;
    }
};

// The edges of part `part` (zero-length ones left out).
std::vector<Segment> part_segments(const MultiPolygon& p, std::size_t part) {
    const std::size_t first = p.first_ring_of_polygon(part);
    const std::size_t end = part + 1 < p.polygon_count() ? p.first_ring_of_polygon(part + 1) : p.ring_count();
    std::vector<Segment> out;
    for (std::size_t r = first; r < end; ++r) {
        const auto v = p.ring(r);
        for (std::size_t k = 0; k < v.size(); ++k) {
            const XY a = v[k], b = v[(k + 1) % v.size()];
            if (a == b) continue;
            out.push_back({before(a, b) ? a : b, before(a, b) ? b : a, static_cast<std::uint32_t>(r - first),
                           static_cast<std::uint32_t>(k)});
        }
    }
    return out;
}

// The first crossing the sweep of one part meets, as a pair of its segments.
std::optional<std::pair<std::uint32_t, std::uint32_t>> sweep(const std::vector<Segment>& segments,
                                                               std::uint64_t& work) {
    // Events: 2 i + 1 inserts segment i at its start, 2 i removes it at its end; at one point, removals first.
    std::vector<std::uint32_t> events(2 * segments.size());
    for (std::size_t i = 0; i < events.size(); ++i) events[i] = static_cast<std::uint32_t>(i);
    const auto point = [&](std::uint32_t e) -> const XY& { return e & 1 ? segments[e >> 1].l : segments[e >> 1].r; };
    std::sort(events.begin(), events.end(), [&](std::uint32_t a, std::uint32_t b) {
        const XY &pa = point(a), &pb = point(b);
        if (before(pa, pb) || before(pb, pa)) return before(pa, pb);
        return (a & 1) != (b & 1) ? (a & 1) < (b & 1) : a < b;
    });
    using Line = std::set<std::uint32_t, Below>;
    Line line(Below{&segments});
    std::vector<Line::iterator> where(segments.size());
    std::optional<std::pair<std::uint32_t, std::uint32_t>> found;
    const auto test = [&](Line::iterator a, Line::iterator b) {
        ++work;
        if (!found && cross(segments[*a], segments[*b])) found = std::pair{*a, *b};
    };
    for (const std::uint32_t e : events) {
        ++work;
        const std::uint32_t id = e >> 1;
        if (e & 1) {
            const auto it = where[id] = line.insert(id).first;
            if (it != line.begin()) test(std::prev(it), it);
            if (std::next(it) != line.end()) test(it, std::next(it));
        } else {
            const auto it = where[id];
            if (it != line.begin() && std::next(it) != line.end()) test(std::prev(it), std::next(it));
            line.erase(it);
        }
        if (found) break;
    }
    return found;
}

}  // namespace

CrossingCheck find_crossing(const MultiPolygon& p) {
    CrossingCheck out;
    out.parts = p.polygon_count();
    for (std::size_t part = 0; part < out.parts && !out.first; ++part) {
        const std::vector<Segment> segments = part_segments(p, part);
        const auto pair = sweep(segments, out.work);
        if (!pair) continue;
        auto [a, b] = *pair;
        const auto key = [&](std::uint32_t s) { return std::pair{segments[s].ring, segments[s].edge}; };
        if (key(b) < key(a)) std::swap(a, b);
        const Segment &s = segments[a], &t = segments[b];
        out.first = PolygonCrossing{part, s.ring, s.edge, t.ring, t.edge, crossing_point(s, t)};
    }
    return out;
}

namespace {

std::string ring_name(std::size_t ring) { return ring == 0 ? "outer ring" : "hole " + std::to_string(ring); }

}  // namespace

std::string crossing_warning(const CrossingCheck& check, const std::string& name) {
    if (!check.first) return {};
    const auto& c = *check.first;
    char at[96];
    std::snprintf(at, sizeof at, "(%.3f, %.3f)", c.at.x, c.at.y);
    const std::string part = check.parts > 1 ? "part " + std::to_string(c.part + 1) + ": " : "";
    return name + ": the polygon's edges cross at " + at + " (" + part + ring_name(c.ring_a) + " edge " +
           std::to_string(c.edge_a + 1) + " and " + ring_name(c.ring_b) + " edge " + std::to_string(c.edge_b + 1) +
           "); a point is inside where the rings enclose it an odd number of times (even-odd rule), which may "
           "not be the area meant";
}

}  // namespace lidarscout
