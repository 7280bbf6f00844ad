// The buckets, the gift-wrapping walk and the certificate of local_delaunay.hpp.
#include "recon/local_delaunay.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "core/error.hpp"
#include "recon/grid_geometry.hpp"

namespace lidarscout::recon {
namespace {

using Point = LocalDelaunay::Point;

constexpr int kMaxWalkSteps = 32;  // a walk longer than this is left to the triangulation
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

double squared_distance(const Point& a, GridXY q) {
    const double dx = static_cast<double>(a.x) - q.x, dy = static_cast<double>(a.y) - q.y;
    return dx * dx + dy * dy;
}

// The point of `pts` nearest to q, other than `skip` (the first of equals), or nullptr.
const Point* nearest(std::span<const Point> pts, GridXY q, const Point* skip = nullptr) {
    const Point* best = nullptr;
    double best_d2 = kInfinity;
    for (const Point& p : pts) {
        if (&p == skip) continue;
        const double d2 = squared_distance(p, q);
        if (d2 < best_d2) best = &p, best_d2 = d2;
    }
    return best;
}

// The apex of the Delaunay triangle of `pts` left of the Delaunay edge a -> b: the point left of
// it whose circle through a and b holds no other point left of it (nullptr: none is left of it).
// The circles through a and b are nested on that side: the circle through a, b and d has its
// centre at the edge's midpoint plus t(d) times its left normal, t(d) = (d - a).(d - b) / (2 x
// orient(a, b, d)), and d lies inside the circle through a, b and c exactly when t(d) < t(c); the
// fractions are compared exactly (128-bit cross products), equal ones by the perturbed in-circle.
const Point* wrap(const Point& a, const Point& b, std::span<const Point> pts) {
    const Point* apex = nullptr;
    std::int64_t best_num = 0, best_den = 1;
    for (const Point& d : pts) {
        const std::int64_t den = orient(a, b, d);
        if (den <= 0) continue;
        const std::int64_t num = (d.x - a.x) * (d.x - b.x) + (d.y - a.y) * (d.y - b.y);
        const __int128 lhs = static_cast<__int128>(num) * best_den, rhs = static_cast<__int128>(best_num) * den;
        if (!apex || lhs < rhs || (lhs == rhs && inside_circle(a, b, *apex, d))) {
            apex = &d, best_num = num, best_den = den;
        }
    }
    return apex;
}

using Triangle = std::array<const Point*, 3>;  // counter-clockwise

// The first Delaunay triangle of the walk: on the edge from the point nearest q to its own
// nearest neighbour (a Delaunay edge), on q's side where there is a triangle there.
std::optional<Triangle> first_triangle(std::span<const Point> pts, GridXY q) {
    const Point* a = nearest(pts, q);
    const Point* b = a ? nearest(pts, xy(*a), a) : nullptr;
    if (!b) return std::nullopt;
    const bool left = orient(xy(*a), xy(*b), q) >= 0;
    const Point *from = left ? a : b, *to = left ? b : a;
    if (const Point* c = wrap(*from, *to, pts)) return Triangle{from, to, c};
    if (const Point* c = wrap(*to, *from, pts)) return Triangle{to, from, c};
    return std::nullopt;  // every point on one line
}

// The edge of t (index k: t[k] -> t[k + 1]) that q lies beyond, or -1 when t holds q.
int edge_beyond(const Triangle& t, GridXY q) {
    for (int k = 0; k < 3; ++k) {
        const GridXY from = xy(*t[k]), to = xy(*t[(k + 1) % 3]);
        const double e = orient(from, to, q);
        if (e < 0 || (e == 0 && !edge_owns_ties(from, to))) return k;
    }
    return -1;
}

// The circumcircle of t in doubles (computed relative to its first corner), and the margin that
// covers its rounding: a point farther than r + slack from the centre is outside it, a circle
// more than r + slack from a line does not reach it.
struct Circle {
    double x, y, r, slack;
};

Circle circumcircle(const Triangle& t) {
    const Point &a = *t[0], &b = *t[1], &c = *t[2];
    const double bx = double(b.x - a.x), by = double(b.y - a.y), cx = double(c.x - a.x), cy = double(c.y - a.y);
    const double d = 2 * (bx * cy - by * cx), b2 = bx * bx + by * by, c2 = cx * cx + cy * cy;
    const double ux = (cy * b2 - by * c2) / d, uy = (bx * c2 - cx * b2) / d;
    const double r = std::sqrt(ux * ux + uy * uy);
    return {double(a.x) + ux, double(a.y) + uy, r, 1e-9 * r + 4};
}

// Where a walk toward q over the Delaunay triangles of `pts` ends: in triangle t, which holds q
// (checked empty of the other points: every step was a Delaunay one, but the check is cheap),
// beyond the hull of the points, or lost (all points on a line, a walk over kMaxWalkSteps).
struct Walk {
    enum Kind { Holds, Outside, Lost } kind = Lost;
    Triangle t{};
    Circle circle{};
};

Walk walk_to(GridXY q, std::span<const Point> pts) {
    if (pts.size() < 3) return {Walk::Outside, {}};  // no triangle at all
    std::optional<Triangle> t = first_triangle(pts, q);
    if (!t) return {Walk::Outside, {}};  // every point on one line: no triangle at all
    for (int step = 0; step < kMaxWalkSteps; ++step) {
        const int k = edge_beyond(*t, q);
        if (k < 0) break;
        const Point &from = *(*t)[k], &to = *(*t)[(k + 1) % 3];  // cross to the other side
        const Point* apex = wrap(to, from, pts);
        if (!apex) return {Walk::Outside, {}};
        t = Triangle{&to, &from, apex};
    }
    if (edge_beyond(*t, q) >= 0) return {Walk::Lost, {}};
    const Point &a = *(*t)[0], &b = *(*t)[1], &c = *(*t)[2];
    const Circle circle = circumcircle(*t);
    const double near2 = (circle.r + circle.slack) * (circle.r + circle.slack);
    for (const Point& d : pts) {
        const double dx = double(d.x) - circle.x, dy = double(d.y) - circle.y;
        if (dx * dx + dy * dy > near2 || &d == &a || &d == &b || &d == &c) continue;
        if (inside_circle(a, b, c, d)) return {Walk::Lost, {}};
    }
    return {Walk::Holds, *t, circle};
}

bool has_long_edge(const Triangle& t, double max_edge) {
    if (!(max_edge > 0)) return false;
    for (int k = 0; k < 3; ++k) {
        if (squared_distance(*t[k], xy(*t[(k + 1) % 3])) > max_edge * max_edge) return true;
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

// Whether the circle lies inside the rectangle [x0, x1] x [y0, y1].
bool circle_inside(const Circle& c, const auto& region) {
    const double reach = c.r + c.slack;
    return c.x - reach > region.x0 && c.x + reach < region.x1 && c.y - reach > region.y0 && c.y + reach < region.y1;
}

}  // namespace

LocalDelaunay::LocalDelaunay(std::span<const GridXY> positions, std::int64_t extent, double points_per_bucket)
    : extent_(extent) {
    if (extent <= 0 || extent > (std::int64_t{1} << 26) || !(points_per_bucket > 0)) {
        throw Error::in_stage("recon", "local Delaunay: bad extent or bucket size (internal error)");
    }
    // The occupied area, from a coarse 64 x 64 lattice, over the points: the area per point.
    constexpr long kCoarse = 64;
    const double coarse = static_cast<double>(extent) / kCoarse;
    std::vector<char> occupied(kCoarse * kCoarse, 0);
    for (const GridXY& p : positions) {
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

    const auto bucket_of = [&](const GridXY& p) {
        return static_cast<std::size_t>(p.y / static_cast<double>(cell_)) * side_ +
               static_cast<std::size_t>(p.x / static_cast<double>(cell_));
    };
    start_.assign(static_cast<std::size_t>(side_) * side_ + 1, 0);
    for (const GridXY& p : positions) {
        if (!(p.x >= 0 && p.y >= 0 && p.x <= static_cast<double>(extent) && p.y <= static_cast<double>(extent))) {
            throw Error::in_stage("recon", "local Delaunay: a position outside the window (internal error)");
        }
        ++start_[bucket_of(p) + 1];
    }
    for (std::size_t b = 1; b < start_.size(); ++b) start_[b] += start_[b - 1];
    const auto by_y_then_x = [](const GridXY& a, const GridXY& b) { return a.y < b.y || (a.y == b.y && a.x < b.x); };
    if (!std::is_sorted(positions.begin(), positions.end(), by_y_then_x)) {
        throw Error::in_stage("recon", "local Delaunay: positions not sorted by (y, x) (internal error)");
    }
    if (positions.size() >= 3) hull_ = convex_hull(positions);
    for (const Point& p : hull_) {
        box_ = {std::min(box_[0], double(p.x)), std::min(box_[1], double(p.y)), std::max(box_[2], double(p.x)),
                std::max(box_[3], double(p.y))};
    }
    sorted_.resize(positions.size());
    std::vector<std::uint32_t> fill(start_.begin(), start_.end() - 1);
    for (std::size_t i = 0; i < positions.size(); ++i) {
        const GridXY& p = positions[i];
        sorted_[fill[bucket_of(p)]++] = {static_cast<std::int64_t>(p.x), static_cast<std::int64_t>(p.y),
                                         static_cast<std::uint32_t>(i)};
    }
}

LocalDelaunay::Found LocalDelaunay::triangle_at(GridXY q, double max_edge, std::size_t max_points) const {
    thread_local std::vector<Point> gathered;
    gathered.clear();
    const double c = static_cast<double>(cell_);
    const long bx = std::clamp<long>(static_cast<long>(std::floor(q.x / c)), 0, side_ - 1);
    const long by = std::clamp<long>(static_cast<long>(std::floor(q.y / c)), 0, side_ - 1);
    gather_ring(bx, by, 0, gathered);
    int gathered_rings = 0;
    for (int ring = 1; ring <= side_; ring = std::max(ring + 1, ring * 3 / 2)) {
        if (ring == 2 && outside_hull(q)) return {Answer::None, {}};  // the data's edge: no triangle
        while (gathered_rings < ring) gather_ring(bx, by, ++gathered_rings, gathered);
        const Region region = region_of(bx, by, ring);
        const bool covers = max_edge > 0 && q.x - max_edge > region.x0 && q.x + max_edge < region.x1 &&
                            q.y - max_edge > region.y0 && q.y + max_edge < region.y1;
        const Walk walk = walk_to(q, gathered);
        if (walk.kind == Walk::Holds) {
            const bool too_long = has_long_edge(walk.t, max_edge);
            if (covers && too_long) return {Answer::None, {}};
            if (circle_inside(walk.circle, region)) {
                if (too_long) return {Answer::None, {}};
                const Point &a = *walk.t[0], &b = *walk.t[1], &c3 = *walk.t[2];
                return {Answer::Triangle, {{a.index, b.index, c3.index}, barycentric(xy(a), xy(b), xy(c3), q)}};
            }
        } else if (walk.kind == Walk::Outside && covers) {
            return {Answer::None, {}};
        }
        const double buckets = (2.0 * ring + 1) * (2.0 * ring + 1);
        if (gathered.size() > max_points || buckets > 16.0 * static_cast<double>(max_points)) break;
    }
    return {Answer::Unproven, {}};
}

bool LocalDelaunay::outside_hull(GridXY q) const {
    if (hull_.size() < 3) return true;
    if (q.x < box_[0] || q.y < box_[1] || q.x > box_[2] || q.y > box_[3]) return true;
    for (std::size_t i = 0; i < hull_.size(); ++i) {
        if (orient(xy(hull_[i]), xy(hull_[(i + 1) % hull_.size()]), q) < 0) return true;
    }
    return false;
}

void LocalDelaunay::gather_ring(long bx, long by, int ring, std::vector<Point>& out) const {
    const auto add = [&](long x, long y) {
        if (x < 0 || y < 0 || x >= side_ || y >= side_) return;
        const std::size_t b = static_cast<std::size_t>(y) * side_ + x;
        out.insert(out.end(), sorted_.begin() + start_[b], sorted_.begin() + start_[b + 1]);
    };
    if (ring == 0) return add(bx, by);
    for (long x = bx - ring; x <= bx + ring; ++x) add(x, by - ring), add(x, by + ring);
    for (long y = by - ring + 1; y <= by + ring - 1; ++y) add(bx - ring, y), add(bx + ring, y);
}

LocalDelaunay::Region LocalDelaunay::region_of(long bx, long by, int ring) const {
    const double c = static_cast<double>(cell_);
    return {bx - ring <= 0 ? -kInfinity : static_cast<double>(bx - ring) * c,
            by - ring <= 0 ? -kInfinity : static_cast<double>(by - ring) * c,
            bx + ring >= side_ - 1 ? kInfinity : static_cast<double>(bx + ring + 1) * c,
            by + ring >= side_ - 1 ? kInfinity : static_cast<double>(by + ring + 1) * c};
}

}  // namespace lidarscout::recon
