// Edge-function triangle rasterization with the top-left rule on a fixed-point grid.
#include "render/triangle_raster.hpp"

#include <algorithm>
#include <cmath>
#include <utility>

namespace lidarscout::render {
namespace {

constexpr int kSubBits = 8;  // 1/256 pixel
constexpr std::int64_t kOne = std::int64_t{1} << kSubBits;
constexpr std::int64_t kHalf = kOne / 2;

struct FixedPoint {
    std::int64_t x, y;
};

FixedPoint snap(const RasterVertex& v) {
    return {static_cast<std::int64_t>(std::lrint(v.x * kOne)), static_cast<std::int64_t>(std::lrint(v.y * kOne))};
}

bool inside_guard_band(const RasterVertex& v) {
    return std::abs(v.x) < kGuardBandPx && std::abs(v.y) < kGuardBandPx;
}

// The edge function of a -> b at p: > 0 on the inside of a triangle with positive area.
std::int64_t edge(FixedPoint a, FixedPoint b, FixedPoint p) {
    return (b.x - a.x) * (p.y - a.y) - (b.y - a.y) * (p.x - a.x);
}

// Top-left rule (rows grow downwards; positive area = clockwise on screen): a pixel centre
// exactly on an edge belongs to the triangle when the edge is a left edge (going up) or a top
// edge (horizontal, going right). The neighbour across the edge walks it the other way, so
// exactly one of the two owns the centre. Returned as the bias added before the >= 0 test.
std::int64_t tie_bias(FixedPoint a, FixedPoint b) {
    const std::int64_t dx = b.x - a.x, dy = b.y - a.y;
    return (dy < 0 || (dy == 0 && dx > 0)) ? 0 : -1;
}

// One edge's value along a scan line, stepped per pixel.
struct EdgeWalker {
    std::int64_t row_start, step_x, step_y, bias;

    EdgeWalker(FixedPoint a, FixedPoint b, FixedPoint first_centre)
        : row_start(edge(a, b, first_centre)), step_x(-(b.y - a.y) * kOne), step_y((b.x - a.x) * kOne),
          bias(tie_bias(a, b)) {}
};

// Per-triangle constants for attribute interpolation: attribute = sum of lambda_i * v_i
// with lambda_i = edge value opposite vertex i / area.
struct Interpolator {
    float inv_area;
    float inv_depth[3];
    float r[3], g[3], b[3];

    std::uint64_t fragment(float e0, float e1, float e2) const {
        const float l0 = e0 * inv_area, l1 = e1 * inv_area, l2 = e2 * inv_area;
        const float depth = 1.0f / (l0 * inv_depth[0] + l1 * inv_depth[1] + l2 * inv_depth[2]);
        const auto channel = [&](const float* c) {
            return static_cast<std::uint8_t>(std::clamp(l0 * c[0] + l1 * c[1] + l2 * c[2], 0.0f, 255.0f) + 0.5f);
        };
        return pack_fragment(depth, pack_rgba(channel(r), channel(g), channel(b)));
    }
};

Interpolator make_interpolator(const RasterVertex* v[3], std::int64_t area, float shade, float depth_scale) {
    Interpolator in{};
    in.inv_area = 1.0f / static_cast<float>(area);
    for (int i = 0; i < 3; ++i) {
        in.inv_depth[i] = 1.0f / (v[i]->depth * depth_scale);
        in.r[i] = v[i]->r * shade;
        in.g[i] = v[i]->g * shade;
        in.b[i] = v[i]->b * shade;
    }
    return in;
}

// The pixel range whose centres (i + 0.5) can lie within [lo, hi] (fixed point), clipped.
std::pair<int, int> pixel_span(std::int64_t lo, std::int64_t hi, int size) {
    const std::int64_t first = (lo - kHalf + kOne - 1) >> kSubBits;  // ceil((lo - half) / one)
    const std::int64_t last = (hi - kHalf) >> kSubBits;              // floor((hi - half) / one)
    return {static_cast<int>(std::max<std::int64_t>(first, 0)),
            static_cast<int>(std::min<std::int64_t>(last, size - 1))};
}

}  // namespace

void draw_triangle(Framebuffer& fb, const RasterVertex& a, const RasterVertex& b, const RasterVertex& c, float shade,
                   float depth_scale) {
    if (!inside_guard_band(a) || !inside_guard_band(b) || !inside_guard_band(c)) return;
    const RasterVertex* v[3] = {&a, &b, &c};
    FixedPoint p[3] = {snap(a), snap(b), snap(c)};
    std::int64_t area = edge(p[0], p[1], p[2]);
    if (area == 0) return;
    if (area < 0) {
        std::swap(p[1], p[2]);
        std::swap(v[1], v[2]);
        area = -area;
    }
    const auto [x0, x1] = pixel_span(std::min({p[0].x, p[1].x, p[2].x}), std::max({p[0].x, p[1].x, p[2].x}),
                                     fb.width());
    const auto [y0, y1] = pixel_span(std::min({p[0].y, p[1].y, p[2].y}), std::max({p[0].y, p[1].y, p[2].y}),
                                     fb.height());
    if (x0 > x1 || y0 > y1) return;

    const FixedPoint first = {std::int64_t{x0} * kOne + kHalf, std::int64_t{y0} * kOne + kHalf};
    // Edge i is opposite vertex i, so its value is vertex i's barycentric weight times area.
    EdgeWalker e[3] = {EdgeWalker(p[1], p[2], first), EdgeWalker(p[2], p[0], first), EdgeWalker(p[0], p[1], first)};
    const Interpolator in = make_interpolator(v, area, shade, depth_scale);
    for (int y = y0; y <= y1; ++y) {
        std::int64_t w0 = e[0].row_start, w1 = e[1].row_start, w2 = e[2].row_start;
        for (int x = x0; x <= x1; ++x) {
            if (((w0 + e[0].bias) | (w1 + e[1].bias) | (w2 + e[2].bias)) >= 0) {
                const auto f = [](std::int64_t e) { return static_cast<float>(e); };
                fb.write_packed(x, y, in.fragment(f(w0), f(w1), f(w2)));
            }
            w0 += e[0].step_x;
            w1 += e[1].step_x;
            w2 += e[2].step_x;
        }
        for (EdgeWalker& walker : e) walker.row_start += walker.step_y;
    }
}

}  // namespace lidarscout::render
