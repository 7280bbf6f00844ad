// Clough-Tocher baseline: curvature-minimising gradient estimation and the split-triangle cubic
// Bezier patches (see cubic.hpp for the method and how it differs from scipy).
#include "recon/cubic.hpp"

#include <algorithm>
#include <cmath>
#include <utility>

#include "recon/grid_geometry.hpp"

namespace lidarscout::recon {
namespace {

// Edges of the real triangles as adjacency lists of the chunk points (CSR).
struct Adjacency {
    std::vector<std::int32_t> start;  // real_count + 1 entries
    std::vector<std::int32_t> neighbour;
};

Adjacency real_edges(const Triangulation& t) {
    std::vector<std::pair<std::int32_t, std::int32_t>> pairs;
    for (std::size_t i = 0; i < t.triangles.size(); ++i) {
        if (!t.is_real(i)) continue;
        const auto& tri = t.triangles[i];
        for (int k = 0; k < 3; ++k) {
            pairs.emplace_back(tri[k], tri[(k + 1) % 3]);
            pairs.emplace_back(tri[(k + 1) % 3], tri[k]);
        }
    }
    std::sort(pairs.begin(), pairs.end());
    pairs.erase(std::unique(pairs.begin(), pairs.end()), pairs.end());
    Adjacency adj;
    adj.start.assign(t.real_count + 1, 0);
    for (const auto& [from, to] : pairs) ++adj.start[from + 1];
    for (std::size_t v = 0; v < t.real_count; ++v) adj.start[v + 1] += adj.start[v];
    adj.neighbour.reserve(pairs.size());
    for (const auto& [from, to] : pairs) adj.neighbour.push_back(to);
    return adj;
}

using Vec2 = std::array<double, 2>;

double dot(const Vec2& a, const Vec2& b) { return a[0] * b[0] + a[1] * b[1]; }

// One Gauss-Seidel step for vertex v: the gradient minimising the curvature of its edges with
// the neighbours' gradients fixed. Returns the new gradient.
Vec2 local_gradient(const Triangulation& t, const Adjacency& adj, std::span<const float> f,
                    const std::vector<Vec2>& grad, std::int32_t v, double scale) {
    double q00 = 0, q01 = 0, q11 = 0, s0 = 0, s1 = 0;
    const GridXY pv = t.vertices[v];
    for (std::int32_t n = adj.start[v]; n < adj.start[v + 1]; ++n) {
        const std::int32_t w = adj.neighbour[n];
        const Vec2 e{(t.vertices[w].x - pv.x) * scale, (t.vertices[w].y - pv.y) * scale};
        const double length_squared = dot(e, e);
        const double inv_l3 = 1.0 / (length_squared * std::sqrt(length_squared));
        const double rhs = (6.0 * (double{f[v]} - f[w]) + 2.0 * dot(grad[w], e)) * inv_l3;
        q00 += 4.0 * e[0] * e[0] * inv_l3;
        q01 += 4.0 * e[0] * e[1] * inv_l3;
        q11 += 4.0 * e[1] * e[1] * inv_l3;
        s0 += rhs * e[0];
        s1 += rhs * e[1];
    }
    const double det = q00 * q11 - q01 * q01;
    return {-(q11 * s0 - q01 * s1) / det, -(q00 * s1 - q01 * s0) / det};
}

// The 10 Bezier ordinates of one sub-triangle (P_i, P_j, S), in the order
// b300 b210 b120 b030 b201 b111 b021 b102 b012 b003 (exponents of P_i, P_j, S).
using Micro = std::array<double, 10>;
// Sub-triangle k is the one opposite vertex k: (P_{k+1}, P_{k+2}, centroid).
using CtTriangle = std::array<Micro, 3>;

// Direction of the cross-boundary derivative of the edge opposite vertex k of triangle t, as
// barycentric direction coordinates (alpha, beta, gamma) of the sub-triangle (P_i, P_j, S).
std::array<double, 3> cross_direction(const Triangulation& t, std::size_t tri_index, int k) {
    const std::int32_t nb = t.neighbours[tri_index][k];
    if (nb < 0 || !t.is_real(static_cast<std::size_t>(nb))) return {-0.5, -0.5, 1.0};  // towards own centroid
    const auto& tri = t.triangles[tri_index];
    const auto& other = t.triangles[nb];
    GridXY centroid{0, 0};
    for (const std::int32_t v : other) {
        centroid.x += t.vertices[v].x / 3.0;
        centroid.y += t.vertices[v].y / 3.0;
    }
    const auto l = barycentric(t.vertices[tri[0]], t.vertices[tri[1]], t.vertices[tri[2]], centroid);
    const int i = (k + 1) % 3, j = (k + 2) % 3;
    const double di = l[i] - 1.0 / 3, dj = l[j] - 1.0 / 3, dk = l[k] - 1.0 / 3;
    return {di - dk, dj - dk, 3.0 * dk};
}

CtTriangle ct_triangle(const Triangulation& t, std::size_t tri_index, std::span<const float> values,
                       const std::vector<Vec2>& grad, double scale) {
    const auto& tri = t.triangles[tri_index];
    std::array<Vec2, 3> p{};
    std::array<double, 3> f{};
    for (int i = 0; i < 3; ++i) {
        p[i] = {t.vertices[tri[i]].x * scale, t.vertices[tri[i]].y * scale};
        f[i] = values[tri[i]];
    }
    const Vec2 s{(p[0][0] + p[1][0] + p[2][0]) / 3.0, (p[0][1] + p[1][1] + p[2][1]) / 3.0};
    // f_i plus a third of the derivative at P_i towards q.
    const auto towards = [&](int i, const Vec2& q) {
        return f[i] + dot(grad[tri[i]], Vec2{q[0] - p[i][0], q[1] - p[i][1]}) / 3.0;
    };
    std::array<std::array<double, 3>, 3> edge{};  // edge[i][j]: next to P_i on edge i-j
    std::array<double, 3> inner{};                // next to P_i towards the centroid
    for (int i = 0; i < 3; ++i) {
        for (int j = 0; j < 3; ++j) edge[i][j] = i == j ? f[i] : towards(i, p[j]);
        inner[i] = towards(i, s);
    }
    std::array<double, 3> mid{};  // centre of the edge opposite vertex k
    for (int k = 0; k < 3; ++k) {
        const int i = (k + 1) % 3, j = (k + 2) % 3;
        const auto [a, b, g] = cross_direction(t, tri_index, k);
        // The cross-boundary derivative along the edge is quadratic with Bezier coefficients
        // d0, d1, d2; it is linear when d1 is their mean.
        const double d0 = a * f[i] + b * edge[i][j] + g * inner[i];
        const double d2 = a * edge[j][i] + b * f[j] + g * inner[j];
        mid[k] = (0.5 * (d0 + d2) - a * edge[i][j] - b * edge[j][i]) / g;
    }
    std::array<double, 3> near_centre{};  // on the segment P_i - S, next to S
    for (int i = 0; i < 3; ++i) near_centre[i] = (inner[i] + mid[(i + 1) % 3] + mid[(i + 2) % 3]) / 3.0;
    const double centre = (near_centre[0] + near_centre[1] + near_centre[2]) / 3.0;
    CtTriangle out{};
    for (int k = 0; k < 3; ++k) {
        const int i = (k + 1) % 3, j = (k + 2) % 3;
        out[k] = {f[i],     edge[i][j], edge[j][i],     f[j],           inner[i],
                  mid[k],   inner[j],   near_centre[i], near_centre[j], centre};
    }
    return out;
}

double evaluate(const CtTriangle& ct, const std::array<float, 3>& l) {
    const int k = (l[0] <= l[1] && l[0] <= l[2]) ? 0 : (l[1] <= l[2] ? 1 : 2);
    const int i = (k + 1) % 3, j = (k + 2) % 3;
    const double u = double{l[i]} - l[k], v = double{l[j]} - l[k], w = 3.0 * l[k];
    const Micro& b = ct[k];
    return b[0] * u * u * u + 3.0 * b[1] * u * u * v + 3.0 * b[2] * u * v * v + b[3] * v * v * v +
           3.0 * b[4] * u * u * w + 6.0 * b[5] * u * v * w + 3.0 * b[6] * v * v * w + 3.0 * b[7] * u * w * w +
           3.0 * b[8] * v * w * w + b[9] * w * w * w;
}

}  // namespace

std::vector<std::array<double, 2>> estimate_gradients(const Triangulation& triangulation, std::span<const float> values,
                                                      std::int64_t grid_extent, const CubicOptions& options) {
    const double scale = 2.0 / static_cast<double>(grid_extent);  // grid units -> patch space
    const Adjacency adj = real_edges(triangulation);
    std::vector<Vec2> grad(triangulation.real_count, Vec2{0.0, 0.0});
    for (int iteration = 0; iteration < options.max_iterations; ++iteration) {
        double worst = 0.0;
        for (std::size_t v = 0; v < triangulation.real_count; ++v) {
            if (adj.start[v] == adj.start[v + 1]) continue;
            const Vec2 g = local_gradient(triangulation, adj, values, grad, static_cast<std::int32_t>(v), scale);
            const double change = std::max(std::abs(g[0] - grad[v][0]), std::abs(g[1] - grad[v][1]));
            worst = std::max(worst, change / std::max({1.0, std::abs(g[0]), std::abs(g[1])}));
            grad[v] = g;
        }
        if (worst < options.tolerance) break;
    }
    return grad;
}

Image cubic_image(const PatchGeometry& geometry, const PointValues& values, std::int64_t grid_extent,
                  const CubicOptions& options) {
    const Triangulation& t = geometry.triangulation;
    const double scale = 2.0 / static_cast<double>(grid_extent);
    Image image(geometry.face_map.size, values.channels);
    std::vector<CtTriangle> patches(t.triangles.size());
    for (int c = 0; c < values.channels; ++c) {
        const std::span<const float> f(values.values.data() + c * values.count, values.count);
        const auto grad = estimate_gradients(t, f, grid_extent, options);
        for (std::size_t i = 0; i < t.triangles.size(); ++i) {
            if (t.is_real(i)) patches[i] = ct_triangle(t, i, f, grad, scale);
        }
        auto plane = image.plane(c);
        for_each_inside_texel(geometry.face_map,
                              [&](std::size_t texel, std::int32_t face, const std::array<float, 3>& l) {
                                  plane[texel] = static_cast<float>(evaluate(patches[face], l));
                              });
    }
    fill_nearest(image, geometry.nearest, values, &geometry.face_map);
    return image;
}

}  // namespace lidarscout::recon
