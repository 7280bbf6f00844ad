// Helpers for the reconstruction tests: synthetic windows of chunk points (random, slender,
// lattice), brute-force references (point location, nearest point) and byte comparison.
#pragma once

#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <functional>
#include <random>
#include <vector>

#include "recon/grid_geometry.hpp"
#include "recon/patch_space.hpp"
#include "recon/triangulation.hpp"

namespace lidarscout::recon::test {

// The patch whose window starts at the origin for the default spec: patch min = (160, 160).
inline constexpr double kPatchMin = 160.0;

using HeightFn = std::function<double(double x, double y)>;  // metres -> metres

// A chunk point at (x, y) metres (window frame: window min = (0, 0)) with z = f(x, y) and a
// colour derived from the position.
inline lidarscout::OverviewPoint point_at(double x, double y, const HeightFn& f) {
    lidarscout::OverviewPoint p;
    p.x = x;
    p.y = y;
    p.z = f(x, y);
    p.rgb = {static_cast<std::uint8_t>(static_cast<int>(x) % 256), static_cast<std::uint8_t>(static_cast<int>(y) % 256),
             static_cast<std::uint8_t>(static_cast<int>(x + y) % 256)};
    return p;
}

// n uniform random points in the default window [0, 960)^2.
inline std::vector<lidarscout::OverviewPoint> random_window(std::size_t n, std::uint64_t seed, const HeightFn& f) {
    std::mt19937_64 rng(seed);
    std::uniform_real_distribution<double> u(0.0, 960.0);
    std::vector<lidarscout::OverviewPoint> out;
    for (std::size_t i = 0; i < n; ++i) {
        const double x = u(rng), y = u(rng);
        out.push_back(point_at(x, y, f));
    }
    return out;
}

inline PatchOptions opts(std::size_t min_points, bool has_rgb = true) {
    PatchOptions o;
    o.min_points = min_points;
    o.has_rgb = has_rgb;
    return o;
}

inline PatchPoints make_patch(const std::vector<lidarscout::OverviewPoint>& points, PatchOptions options = {}) {
    return make_patch_points(points, kPatchMin, kPatchMin, options);
}

// Rolling synthetic terrain (metres), smooth with some detail.
inline double terrain(double x, double y) {
    return 300.0 + 40.0 * std::sin(x / 150.0) * std::cos(y / 110.0) + 0.05 * x - 0.02 * y +
           5.0 * std::sin(x / 23.0 + y / 31.0);
}

// Brute force: every triangle (real or padding) that owns texel centre p under the tie rule.
inline std::vector<std::int32_t> owners(const Triangulation& t, GridXY p) {
    std::vector<std::int32_t> out;
    for (std::size_t i = 0; i < t.triangles.size(); ++i) {
        const auto& tri = t.triangles[i];
        if (triangle_owns(t.vertices[tri[0]], t.vertices[tri[1]], t.vertices[tri[2]], p)) {
            out.push_back(static_cast<std::int32_t>(i));
        }
    }
    return out;
}

// Brute force nearest point (lowest index among equals), -1 when empty.
inline std::int32_t brute_nearest(const std::vector<GridXY>& points, GridXY p) {
    std::int32_t best = -1;
    double best_d = INFINITY;
    for (std::size_t i = 0; i < points.size(); ++i) {
        const double d = squared_distance(points[i], p);
        if (d < best_d) {
            best_d = d;
            best = static_cast<std::int32_t>(i);
        }
    }
    return best;
}

inline bool same_bytes(const Image& a, const Image& b) {
    return a.size == b.size && a.channels == b.channels && a.values.size() == b.values.size() &&
           (a.values.empty() || std::memcmp(a.values.data(), b.values.data(), a.values.size() * sizeof(float)) == 0);
}

}  // namespace lidarscout::recon::test
