// Exact geometry on the fixed-point texel grid (see patch_space.hpp): texel centres, the
// orientation test, squared distances, the tie rule for texel centres on a triangle edge, and
// a triangle's circumcircle (and whether it stays near a texel centre).
// Grid coordinates are integers below 2^25 held in doubles, so every product of two
// differences is below 2^50 and the expressions here are computed without rounding (all but the
// circumcircle test, which leaves room for it).
#pragma once

#include <array>
#include <cmath>
#include <cstdint>

#include "recon/patch_space.hpp"

namespace lidarscout::recon {

// The centre of texel index i (column or row), in grid units.
inline double texel_centre(int i) { return (i + 0.5) * static_cast<double>(kGridUnitsPerTexel); }

// Twice the signed area of (a, b, p): > 0 when p is left of a -> b (counter-clockwise).
inline double orient(GridXY a, GridXY b, GridXY p) {
    return (b.x - a.x) * (p.y - a.y) - (b.y - a.y) * (p.x - a.x);
}

inline double squared_distance(GridXY a, GridXY b) {
    const double dx = a.x - b.x, dy = a.y - b.y;
    return dx * dx + dy * dy;
}

// The tie rule: a texel centre exactly on the directed edge a -> b of a counter-clockwise
// triangle belongs to that triangle when the edge points up, or right when horizontal. The
// neighbour across the edge walks it the other way, so exactly one of the two owns the point;
// a centre exactly on a vertex belongs to exactly one triangle of the vertex's fan.
inline bool edge_owns_ties(GridXY a, GridXY b) { return b.y > a.y || (b.y == a.y && b.x > a.x); }

// Whether p lies in the counter-clockwise triangle (a, b, c) under the tie rule.
inline bool triangle_owns(GridXY a, GridXY b, GridXY c, GridXY p) {
    const auto inside = [p](GridXY from, GridXY to) {
        const double e = orient(from, to, p);
        return e > 0.0 || (e == 0.0 && edge_owns_ties(from, to));
    };
    return inside(b, c) && inside(c, a) && inside(a, b);
}

// Barycentric coordinates of p in the counter-clockwise triangle (a, b, c) (non-degenerate).
inline std::array<double, 3> barycentric(GridXY a, GridXY b, GridXY c, GridXY p) {
    const double inv_area = 1.0 / orient(a, b, c);
    const double la = orient(b, c, p) * inv_area;
    const double lb = orient(c, a, p) * inv_area;
    return {la, lb, 1.0 - la - lb};
}

// The circumcircle of the triangle (a, b, c) (non-degenerate), computed in doubles: its centre
// and radius, grown by a few units and a relative 1e-9 to cover their rounding.
struct Circle {
    double x = 0, y = 0, radius = 0;
};
inline Circle circumcircle(GridXY a, GridXY b, GridXY c) {
    const double bx = b.x - a.x, by = b.y - a.y, cx = c.x - a.x, cy = c.y - a.y;
    const double d = 2.0 * (bx * cy - by * cx);
    const double b2 = bx * bx + by * by, c2 = cx * cx + cy * cy;
    const double ux = (cy * b2 - by * c2) / d, uy = (bx * c2 - cx * b2) / d;  // the centre, from a
    const double radius = std::sqrt(ux * ux + uy * uy);
    return {a.x + ux, a.y + uy, radius * (1.0 + 1e-9) + 4.0};
}

// Whether the circle lies inside the disc of radius `reach` around q.
inline bool circle_within(const Circle& circle, GridXY q, double reach) {
    return std::hypot(circle.x - q.x, circle.y - q.y) + circle.radius < reach * (1.0 - 1e-9);
}

}  // namespace lidarscout::recon
