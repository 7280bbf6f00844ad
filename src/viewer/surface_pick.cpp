// Ray against heightmaps: a slab test against each patch's box, then a march in steps of a
// quarter texel with the crossing refined by bisection.
#include "viewer/surface_pick.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

#include "render/framebuffer.hpp"
#include "viewer/cursor_readout.hpp"

namespace lidarscout::viewer {
namespace {

constexpr float kNaN = std::numeric_limits<float>::quiet_NaN();

struct Ray {
    std::array<double, 3> origin, dir;
    std::array<double, 3> at(double t) const {
        return {origin[0] + t * dir[0], origin[1] + t * dir[1], origin[2] + t * dir[2]};
    }
};

// [t0, t1] of the ray inside the box, clipped to [near, far]; empty when it misses.
std::optional<std::pair<double, double>> slab(const Ray& ray, const std::array<double, 3>& lo,
                                              const std::array<double, 3>& hi, double near, double far) {
    double t0 = near, t1 = far;
    for (int i = 0; i < 3; ++i) {
        if (std::abs(ray.dir[i]) < 1e-15) {
            if (ray.origin[i] < lo[i] || ray.origin[i] > hi[i]) return std::nullopt;
            continue;
        }
        double a = (lo[i] - ray.origin[i]) / ray.dir[i], b = (hi[i] - ray.origin[i]) / ray.dir[i];
        if (a > b) std::swap(a, b);
        t0 = std::max(t0, a), t1 = std::min(t1, b);
    }
    if (t0 > t1) return std::nullopt;
    return std::pair{t0, t1};
}

// Height of the ray above the surface at depth t (NaN over a hole).
double above(const PatchHeightmap& h, const Ray& ray, double t) {
    const auto p = ray.at(t);
    const float s = surface_height(h, p[0], p[1]);
    return std::isnan(s) ? NAN : p[2] - s;
}

// The depth where the ray first goes from above the surface to on or below it, within [t0, t1].
std::optional<double> first_crossing(const PatchHeightmap& h, const Ray& ray, double t0, double t1) {
    const double horizontal = std::hypot(ray.dir[0], ray.dir[1]);
    const double step = 0.25 * h.texel_m / std::max(horizontal, 1e-9);
    const int steps = static_cast<int>(std::clamp(std::ceil((t1 - t0) / step), 1.0, 8.0 * h.size));
    double prev_t = t0, prev = above(h, ray, t0);
    for (int k = 1; k <= steps; ++k) {
        const double t = t0 + (t1 - t0) * k / steps, now = above(h, ray, t);
        if (prev > 0 && now <= 0) {
            double a = prev_t, b = t;
            for (int i = 0; i < 40; ++i) {
                const double m = 0.5 * (a + b), v = above(h, ray, m);
                (v > 0 || std::isnan(v) ? a : b) = m;  // a hole counts as above: b keeps a defined height
            }
            return b;
        }
        prev_t = t, prev = now;
    }
    return std::nullopt;
}

std::array<double, 2> height_range(const PatchHeightmap& h) {
    double lo = INFINITY, hi = -INFINITY;
    for (const float v : h.heights) {
        if (!std::isnan(v)) lo = std::min<double>(lo, v), hi = std::max<double>(hi, v);
    }
    return {lo, hi};
}

std::uint32_t texel_colour(const PatchHeightmap& h, double x, double y) {
    if (h.colours.empty()) return render::pack_rgba(128, 128, 128);
    const int col = std::clamp(static_cast<int>(std::floor((x - h.origin_x) / h.texel_m)), 0, h.size - 1);
    const int row = std::clamp(static_cast<int>(std::floor((y - h.origin_y) / h.texel_m)), 0, h.size - 1);
    return h.colours[static_cast<std::size_t>(row) * h.size + col];
}

}  // namespace

float surface_height(const PatchHeightmap& h, double x, double y) {
    const double side = h.size * h.texel_m;
    if (!(x >= h.origin_x && y >= h.origin_y && x <= h.origin_x + side && y <= h.origin_y + side)) return kNaN;
    const double u = (x - h.origin_x) / h.texel_m - 0.5, v = (y - h.origin_y) / h.texel_m - 0.5;
    const int i0 = std::clamp(static_cast<int>(std::floor(u)), 0, h.size - 2);
    const int j0 = std::clamp(static_cast<int>(std::floor(v)), 0, h.size - 2);
    const double fu = u - i0, fv = v - j0;  // beyond [0, 1] in the outer half texels: extrapolated, as drawn
    const auto at = [&](int i, int j) { return h.heights[static_cast<std::size_t>(j) * h.size + i]; };
    const float a = at(i0, j0), b = at(i0 + 1, j0), c = at(i0, j0 + 1), d = at(i0 + 1, j0 + 1);
    if (std::isnan(a) || std::isnan(b) || std::isnan(c) || std::isnan(d)) {
        return at(std::clamp(static_cast<int>(std::lround(u)), 0, h.size - 1),
                  std::clamp(static_cast<int>(std::lround(v)), 0, h.size - 1));  // NaN: a hole
    }
    return static_cast<float>((a * (1 - fu) + b * fu) * (1 - fv) + (c * (1 - fu) + d * fu) * fv);
}

std::optional<PickedPoint> pick_surface(const SceneSnapshot& snapshot, const render::Camera& camera, double px,
                                        double py) {
    const Ray ray{{camera.x, camera.y, camera.z}, pixel_ray(camera, px, py)};
    std::optional<PickedPoint> best;
    for (const auto& patch : snapshot.heightmaps) {
        const PatchHeightmap& h = *patch;
        const auto [zlo, zhi] = height_range(h);
        if (!(zlo <= zhi)) continue;
        const double side = h.size * h.texel_m;
        const double far = best ? best->depth : camera.far_m;
        const auto span = slab(ray, {h.origin_x, h.origin_y, zlo}, {h.origin_x + side, h.origin_y + side, zhi},
                               camera.near_m, far);
        if (!span) continue;
        const auto t = first_crossing(h, ray, span->first, span->second);
        if (!t) continue;
        const auto p = ray.at(*t);
        PickedPoint hit;
        hit.x = p[0], hit.y = p[1], hit.z = surface_height(h, p[0], p[1]);
        const std::uint32_t rgba = texel_colour(h, p[0], p[1]);
        hit.r = render::red(rgba), hit.g = render::green(rgba), hit.b = render::blue(rgba);
        hit.surface = true;
        hit.depth = *t;
        best = hit;
    }
    return best;
}

std::optional<PickedPoint> pick(const SceneSnapshot& snapshot, const render::Camera& camera, double px, double py,
                                const PickOptions& options) {
    auto point = pick_point(snapshot, camera, px, py, options);
    auto surface = pick_surface(snapshot, camera, px, py);
    // a point drawn on the surface wins; one well behind it (hidden by a hill) does not
    if (point && (!surface || point->depth <= surface->depth * 1.01 + 1.0)) return point;
    return surface;
}

}  // namespace lidarscout::viewer
