// The buckets, the nearest-point search, the gift-wrapping step and the walk of local_delaunay.hpp.
#include "recon/local_delaunay.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "core/error.hpp"
#include "recon/grid_geometry.hpp"

namespace lidarscout::recon {
namespace {

using Point = LocalDelaunay::Point;

constexpr double kInfinity = std::numeric_limits<double>::infinity();

GridXY xy(const Point& p) { return {static_cast<double>(p.x), static_cast<double>(p.y)}; }

// Twice the signed area of (a, b, c), exact: coordinates below 2^26, products below 2^53.
std::int64_t orient(const Point& a, const Point& b, const Point& c) {
    return (b.x - a.x) * (c.y - a.y) - (b.y - a.y) * (c.x - a.x);
}

// Whether d lies inside the circumcircle of the counter-clockwise triangle (a, b, c), exact (each
// term below 2^107). Points on the circle are decided by CGAL's symbolic perturbation
// (Triangulation_2::side_of_oriented_circle with perturb: the lexicographically largest of the
// four points moves first), which is what makes its Delaunay triangulation unique, so that the
// triangles found here are the ones it builds.
bool inside_circle(const Point& a, const Point& b, const Point& c, const Point& d) {
    {  // in doubles first: the differences, squares and 2 x 2 minors are exact, the rest within
       // a few ulps of the permanent, so a determinant beyond this bound has its sign
        const double adx = double(a.x - d.x), ady = double(a.y - d.y), bdx = double(b.x - d.x),
                     bdy = double(b.y - d.y), cdx = double(c.x - d.x), cdy = double(c.y - d.y);
        const double alift = adx * adx + ady * ady, blift = bdx * bdx + bdy * bdy, clift = cdx * cdx + cdy * cdy;
        const double bc = bdx * cdy - bdy * cdx, ca = cdx * ady - cdy * adx, ab = adx * bdy - ady * bdx;
        const double det = alift * bc + blift * ca + clift * ab;
        const double permanent = alift * std::abs(bc) + blift * std::abs(ca) + clift * std::abs(ab);
        const double bound = 1e-14 * permanent;
        if (det > bound) return true;
        if (det < -bound) return false;
    }
    const __int128 adx = a.x - d.x, ady = a.y - d.y, bdx = b.x - d.x, bdy = b.y - d.y, cdx = c.x - d.x,
                   cdy = c.y - d.y;
    const __int128 alift = adx * adx + ady * ady, blift = bdx * bdx + bdy * bdy, clift = cdx * cdx + cdy * cdy;
    const __int128 det = alift * (bdx * cdy - bdy * cdx) - blift * (adx * cdy - ady * cdx) +
                         clift * (adx * bdy - ady * bdx);
    if (det != 0) return det > 0;
    std::array<const Point*, 4> order{&a, &b, &c, &d};
    std::sort(order.begin(), order.end(),
              [](const Point* p, const Point* q) { return p->x < q->x || (p->x == q->x && p->y < q->y); });
    for (int i = 3; i > 0; --i) {
        if (order[i] == &d) return false;
        std::int64_t o = 0;
        if (order[i] == &c) o = orient(a, b, d);
        else if (order[i] == &b) o = orient(a, d, c);
        else o = orient(d, b, c);
        if (o != 0) return o > 0;
    }
    return false;
}

// The squared distance from (x, y) to the rectangle [x0, x1] x [y0, y1] (0 inside).
double squared_distance_to(const auto& rect, double x, double y) {
    const double dx = std::max({rect.x0 - x, 0.0, x - rect.x1}), dy = std::max({rect.y0 - y, 0.0, y - rect.y1});
    return dx * dx + dy * dy;
}

using Triangle = std::array<const Point*, 3>;  // counter-clockwise

// The edge of t (index k: t[k] -> t[k + 1]) that q lies beyond, or -1 when t holds q.
int edge_beyond(const Triangle& t, GridXY q) {
    for (int k = 0; k < 3; ++k) {
        const GridXY from = xy(*t[k]), to = xy(*t[(k + 1) % 3]);
        const double e = orient(from, to, q);
        if (e < 0 || (e == 0 && !edge_owns_ties(from, to))) return k;
    }
    return -1;
}

bool has_long_edge(const Triangle& t, double max_edge) {
    if (!(max_edge > 0)) return false;
    for (int k = 0; k < 3; ++k) {
        if (squared_distance(xy(*t[k]), xy(*t[(k + 1) % 3])) > max_edge * max_edge) return true;
    }
    return false;
}

// The convex hull (counter-clockwise, no collinear points) of positions sorted by (y, x): the
// monotone chain, its two chains running up the right side and down the left.
std::vector<Point> convex_hull(std::span<const GridXY> sorted) {
    std::vector<Point> hull;
    const auto push = [&](const GridXY& g, std::size_t floor) {
        const Point p{static_cast<std::int64_t>(g.x), static_cast<std::int64_t>(g.y), 0};
        while (hull.size() >= floor + 2 && orient(hull[hull.size() - 2], hull.back(), p) <= 0) hull.pop_back();
        hull.push_back(p);
    };
    for (const GridXY& g : sorted) push(g, 0);
    const std::size_t right = hull.size() - 1;
    for (std::size_t i = sorted.size() - 1; i-- > 0;) push(sorted[i], right);
    hull.pop_back();  // the first point again
    return hull;
}

}  // namespace

LocalDelaunay::LocalDelaunay(std::span<const GridXY> positions, std::int64_t extent, double points_per_bucket)
    : extent_(extent) {
    if (extent <= 0 || extent > (std::int64_t{1} << 26) || !(points_per_bucket > 0)) {
        throw Error::in_stage("recon", "local Delaunay: bad extent or bucket size (internal error)");
    }
    const auto by_y_then_x = [](const GridXY& a, const GridXY& b) { return a.y < b.y || (a.y == b.y && a.x < b.x); };
    if (!std::is_sorted(positions.begin(), positions.end(), by_y_then_x) ||
        std::adjacent_find(positions.begin(), positions.end()) != positions.end()) {
        throw Error::in_stage("recon", "local Delaunay: positions not distinct and sorted by (y, x) (internal error)");
    }
    if (positions.size() >= 3) hull_ = convex_hull(positions);
    for (const Point& p : hull_) {
        box_ = {std::min(box_.x0, double(p.x)), std::min(box_.y0, double(p.y)), std::max(box_.x1, double(p.x)),
                std::max(box_.y1, double(p.y))};
    }
    // The occupied area, from a coarse 64 x 64 lattice, over the points: the area per point.
    constexpr long kCoarse = 64;
    const double coarse = static_cast<double>(extent) / kCoarse;
    std::vector<char> occupied(kCoarse * kCoarse, 0);
    for (const GridXY& p : positions) {
        if (!(p.x >= 0 && p.y >= 0 && p.x <= static_cast<double>(extent) && p.y <= static_cast<double>(extent))) {
            throw Error::in_stage("recon", "local Delaunay: a position outside the window (internal error)");
        }
        const long cx = std::min<long>(static_cast<long>(p.x / coarse), kCoarse - 1);
        const long cy = std::min<long>(static_cast<long>(p.y / coarse), kCoarse - 1);
        occupied[cy * kCoarse + cx] = 1;
    }
    const double area = static_cast<double>(std::count(occupied.begin(), occupied.end(), 1)) * coarse * coarse;
    const double per_point = positions.empty() ? area : area / static_cast<double>(positions.size());
    // at most kMaxSide buckets a side (16 MiB of them), at least 64 grid units each
    constexpr std::int64_t kMaxSide = 2048;
    const std::int64_t smallest = std::max<std::int64_t>(64, (extent + kMaxSide - 1) / kMaxSide);
    cell_ = std::clamp<std::int64_t>(std::llround(std::sqrt(points_per_bucket * per_point)), smallest, extent);
    side_ = static_cast<long>(extent / cell_) + 1;
    group_ = std::max<long>(4, side_ / 128);
    groups_ = (side_ + group_ - 1) / group_;

    const auto column = [&](double v) { return static_cast<long>(v / static_cast<double>(cell_)); };
    const auto bucket_of = [&](const GridXY& p) { return static_cast<std::size_t>(column(p.y)) * side_ + column(p.x); };
    start_.assign(static_cast<std::size_t>(side_) * side_ + 1, 0);
    grouped_.assign(static_cast<std::size_t>(groups_) * groups_, 0);
    for (const GridXY& p : positions) {
        ++start_[bucket_of(p) + 1];
        ++grouped_[static_cast<std::size_t>(column(p.y) / group_) * groups_ + column(p.x) / group_];
    }
    for (std::size_t b = 1; b < start_.size(); ++b) start_[b] += start_[b - 1];
    sorted_.resize(positions.size());
    std::vector<std::uint32_t> fill(start_.begin(), start_.end() - 1);
    for (std::size_t i = 0; i < positions.size(); ++i) {
        const GridXY& p = positions[i];
        sorted_[fill[bucket_of(p)]++] = {static_cast<std::int64_t>(p.x), static_cast<std::int64_t>(p.y),
                                         static_cast<std::uint32_t>(i)};
    }
}

template <typename Wanted, typename Visit>
void LocalDelaunay::scan(const Rect& area, const Wanted& wanted, const Visit& visit) const {
    const double c = static_cast<double>(cell_), g = c * static_cast<double>(group_);
    const auto first = [&](double v) { return std::max(0L, static_cast<long>(std::floor(std::max(v, -1.0) / c))); };
    const auto last = [&](double v) {
        return std::min(side_ - 1, static_cast<long>(std::floor(std::min(v, double(extent_) + c) / c)));
    };
    const long bx0 = first(area.x0), by0 = first(area.y0), bx1 = last(area.x1), by1 = last(area.y1);
    for (long gy = by0 / group_; gy <= by1 / group_; ++gy) {
        for (long gx = bx0 / group_; gx <= bx1 / group_; ++gx) {
            if (!grouped_[static_cast<std::size_t>(gy) * groups_ + gx]) continue;
            if (!wanted(Rect{double(gx) * g, double(gy) * g, double(gx + 1) * g, double(gy + 1) * g})) continue;
            for (long by = std::max(by0, gy * group_); by <= std::min(by1, (gy + 1) * group_ - 1); ++by) {
                for (long bx = std::max(bx0, gx * group_); bx <= std::min(bx1, (gx + 1) * group_ - 1); ++bx) {
                    const std::size_t b = static_cast<std::size_t>(by) * side_ + bx;
                    if (start_[b] == start_[b + 1]) continue;
                    if (!wanted(Rect{double(bx) * c, double(by) * c, double(bx + 1) * c, double(by + 1) * c})) continue;
                    for (std::uint32_t i = start_[b]; i < start_[b + 1]; ++i) visit(sorted_[i]);
                }
            }
        }
    }
}

const Point* LocalDelaunay::nearest(GridXY q, const Point* skip, double limit) const {
    const Point* best = nullptr;
    double best_d2 = kInfinity;
    const auto wanted = [&](const Rect& r) { return squared_distance_to(r, q.x, q.y) <= best_d2; };
    const auto visit = [&](const Point& p) {
        const double d2 = squared_distance(xy(p), q);
        if (&p != skip && d2 < best_d2) best = &p, best_d2 = d2;
    };
    for (double h = static_cast<double>(cell_);; h *= 2) {  // squares of growing half-side h around q
        scan({q.x - h, q.y - h, q.x + h, q.y + h}, wanted, visit);
        if (best && best_d2 <= h * h) return best;  // every point within h has been seen
        if (h >= limit) return best && best_d2 <= limit * limit ? best : nullptr;
        if (q.x - h <= 0 && q.y - h <= 0 && q.x + h >= double(extent_) && q.y + h >= double(extent_)) return best;
    }
}

// The circles through a and b are nested on its left: the circle through a, b and d has its centre
// at the edge's midpoint plus t(d) times its left normal, t(d) = (d - a).(d - b) / (2 x orient(a, b,
// d)), and d lies inside the circle through a, b and c exactly when t(d) < t(c); the fractions are
// compared exactly (128-bit cross products), equal ones by the perturbed in-circle test. Buckets are
// visited in rings around the midpoint's, so that near points shrink the circle early, skipping
// those right of the edge or outside the best circle so far, until that circle lies inside the
// rings seen.
const Point* LocalDelaunay::wrap(const Point& a, const Point& b) const {
    const Point* apex = nullptr;
    std::int64_t best_num = 0, best_den = 1;
    double cx = 0, cy = 0, reach = kInfinity;  // the best circle so far, grown by its rounding
    const double mx = 0.5 * double(a.x + b.x), my = 0.5 * double(a.y + b.y);
    const double nx = -double(b.y - a.y), ny = double(b.x - a.x);  // the left normal
    const double c = static_cast<double>(cell_);
    // a rectangle partly left of the edge that the best circle so far reaches
    const auto wanted = [&](const Rect& r) {
        const double ex = nx > 0 ? r.x1 : r.x0, ey = ny > 0 ? r.y1 : r.y0;  // its corner farthest left
        return nx * (ex - double(a.x)) + ny * (ey - double(a.y)) > 0 && squared_distance_to(r, cx, cy) <= reach * reach;
    };
    const auto visit_bucket = [&](long bx, long by) {
        const std::size_t bucket = static_cast<std::size_t>(by) * side_ + bx;
        if (start_[bucket] == start_[bucket + 1]) return;
        if (!wanted(Rect{double(bx) * c, double(by) * c, double(bx + 1) * c, double(by + 1) * c})) return;
        for (std::uint32_t i = start_[bucket]; i < start_[bucket + 1]; ++i) {
            const Point& d = sorted_[i];
            const std::int64_t den = orient(a, b, d);
            if (den <= 0 || &d == apex) continue;
            const std::int64_t num = (d.x - a.x) * (d.x - b.x) + (d.y - a.y) * (d.y - b.y);
            const __int128 lhs = static_cast<__int128>(num) * best_den, rhs = static_cast<__int128>(best_num) * den;
            if (apex && !(lhs < rhs || (lhs == rhs && inside_circle(a, b, *apex, d)))) continue;
            apex = &d, best_num = num, best_den = den;
            const double t = double(num) / (2.0 * double(den));
            cx = mx + t * nx, cy = my + t * ny;
            const double r2 = (cx - double(a.x)) * (cx - double(a.x)) + (cy - double(a.y)) * (cy - double(a.y));
            const double radius = std::sqrt(r2);
            reach = radius + 1e-9 * radius + 4;
        }
    };
    // The rings of cells of `unit` buckets around the midpoint's, each cell visited by visit_cell;
    // true when the best circle lies inside the rings seen (or they hold every bucket).
    const auto rings = [&](long unit, long cells, long first, long last, const auto& visit_cell) {
        const long cx0 = std::clamp<long>(static_cast<long>(mx / c), 0, side_ - 1) / unit;
        const long cy0 = std::clamp<long>(static_cast<long>(my / c), 0, side_ - 1) / unit;
        const double u = c * double(unit);
        for (long k = first; k <= last; ++k) {
            const long x0 = cx0 - k, x1 = cx0 + k, y0 = cy0 - k, y1 = cy0 + k;
            for (long x = std::max(x0, 0L); x <= std::min(x1, cells - 1); ++x) {
                if (y0 >= 0) visit_cell(x, y0);
                if (y1 < cells && k > 0) visit_cell(x, y1);
            }
            for (long y = std::max(y0 + 1, 0L); y <= std::min(y1 - 1, cells - 1); ++y) {
                if (x0 >= 0) visit_cell(x0, y);
                if (x1 < cells && k > 0) visit_cell(x1, y);
            }
            // the rings seen cover this (unbounded where they reach the last cells: no point beyond)
            const Rect seen{x0 <= 0 ? -kInfinity : double(x0) * u, y0 <= 0 ? -kInfinity : double(y0) * u,
                            x1 >= cells - 1 ? kInfinity : double(x1 + 1) * u,
                            y1 >= cells - 1 ? kInfinity : double(y1 + 1) * u};
            if (apex && cx - reach > seen.x0 && cx + reach < seen.x1 && cy - reach > seen.y0 && cy + reach < seen.y1) {
                return true;
            }
            if (seen.x0 < 0 && seen.y0 < 0 && seen.x1 == kInfinity && seen.y1 == kInfinity) return true;
        }
        return false;
    };
    // near rings bucket by bucket; then, for the few circles that reach far (slivers along a hull,
    // wide voids), rings of groups of buckets, skipping the empty groups and those the circle misses
    constexpr long kBucketRings = 8;
    if (rings(1, side_, 0, kBucketRings, visit_bucket)) return apex;
    if (!apex && nothing_left_of(a, b)) return nullptr;  // a hull edge
    const auto visit_group = [&](long gx, long gy) {
        if (!grouped_[static_cast<std::size_t>(gy) * groups_ + gx]) return;
        const double g = c * double(group_);
        if (!wanted(Rect{double(gx) * g, double(gy) * g, double(gx + 1) * g, double(gy + 1) * g})) return;
        for (long by = gy * group_; by < std::min(side_, (gy + 1) * group_); ++by) {
            for (long bx = gx * group_; bx < std::min(side_, (gx + 1) * group_); ++bx) visit_bucket(bx, by);
        }
    };
    rings(group_, groups_, 0, groups_, visit_group);
    return apex;
}

bool LocalDelaunay::nothing_left_of(const Point& a, const Point& b) const {
    return std::none_of(hull_.begin(), hull_.end(), [&](const Point& h) { return orient(a, b, h) > 0; });
}

LocalDelaunay::Found LocalDelaunay::triangle_at(GridXY q, double max_edge, Hint* hint, int max_steps) const {
    const auto none = [&] {
        if (hint) hint->has_last = false;
        return Found{Answer::None, {}};
    };
    if (q.x < box_.x0 || q.y < box_.y0 || q.x > box_.x1 || q.y > box_.y1) return none();  // beyond the hull
    Triangle t;
    if (hint && hint->has_last) {
        t = hint->last;
    } else {
        // a short triangle over q has a corner within max_edge / sqrt(3) of it
        const Point* a = nearest(q, nullptr, max_edge > 0 ? max_edge / std::sqrt(3.0) : kInfinity);
        const Point* b = a ? nearest(xy(*a), a, kInfinity) : nullptr;
        if (!b) return none();
        // the first triangle, on the edge from q's nearest point to its nearest neighbour (a
        // Delaunay edge), on q's side where there is one
        const bool left = orient(xy(*a), xy(*b), q) >= 0;
        const Point *from = left ? a : b, *to = left ? b : a;
        if (const Point* c = wrap(*from, *to)) t = {from, to, c};
        else if (const Point* c2 = wrap(*to, *from)) t = {to, from, c2};
        else return none();  // every point on one line: no triangle at all
    }
    for (int step = 0;; ++step) {
        const int k = edge_beyond(t, q);
        if (k < 0) break;
        if (step == max_steps) {
            if (hint) hint->has_last = false;
            return {Answer::Unproven, {}};
        }
        const Point &edge_from = *t[k], &edge_to = *t[(k + 1) % 3];  // cross to the other side
        const Point* apex = wrap(edge_to, edge_from);
        if (!apex) return none();  // q beyond the hull
        t = {&edge_to, &edge_from, apex};
    }
    if (hint) hint->last = t, hint->has_last = true;
    if (has_long_edge(t, max_edge)) return {Answer::None, {}};
    const auto weights = barycentric(xy(*t[0]), xy(*t[1]), xy(*t[2]), q);
    return {Answer::Triangle, {{t[0]->index, t[1]->index, t[2]->index}, weights}};
}

}  // namespace lidarscout::recon
