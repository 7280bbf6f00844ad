// Resolve: framebuffer -> RGBA8 with background and eye-dome lighting, rows spread over the pool.
#include "render/resolve.hpp"

#include <algorithm>
#include <cmath>
#include <string>

#include "core/error.hpp"

namespace lidarscout::render {
namespace {

constexpr int kRowsPerJob = 16;
constexpr float kNoDepth = -1.0f;  // marks empty pixels in the log-depth buffer

std::uint32_t darken(std::uint32_t rgba, float factor) {
    const auto scale = [factor](std::uint8_t c) { return static_cast<std::uint8_t>(c * factor + 0.5f); };
    return pack_rgba(scale(red(rgba)), scale(green(rgba)), scale(blue(rgba)), alpha(rgba));
}

void copy_rows(const Framebuffer& fb, std::uint32_t background, int y0, int y1, RgbaImage& out) {
    const std::size_t w = static_cast<std::size_t>(fb.width());
    for (std::size_t i = y0 * w; i < y1 * w; ++i) {
        const std::uint64_t v = fb.data()[i];
        out.pixels[i] = v == kEmpty ? background : fragment_rgba(v);
    }
}

void log_depth_rows(const Framebuffer& fb, int y0, int y1, std::vector<float>& log_depth) {
    const std::size_t w = static_cast<std::size_t>(fb.width());
    for (std::size_t i = y0 * w; i < y1 * w; ++i) {
        const std::uint64_t v = fb.data()[i];
        log_depth[i] = v == kEmpty ? kNoDepth : std::log2(fragment_depth(v));
    }
}

// Mean of max(0, d - neighbour) over the 4 neighbours at radius r (missing ones count 0).
float edl_response(const std::vector<float>& log_depth, int width, int height, int x, int y, int r, float d) {
    const int nx[4] = {x - r, x + r, x, x};
    const int ny[4] = {y, y, y - r, y + r};
    float sum = 0.0f;
    for (int k = 0; k < 4; ++k) {
        if (nx[k] < 0 || nx[k] >= width || ny[k] < 0 || ny[k] >= height) continue;
        const float n = log_depth[static_cast<std::size_t>(ny[k]) * width + nx[k]];
        if (n != kNoDepth) sum += std::max(0.0f, d - n);
    }
    return 0.25f * sum;
}

void edl_rows(const std::vector<float>& log_depth, const ResolveSettings& s, int y0, int y1, RgbaImage& out) {
    const float k = kEdlScale * s.edl_strength;
    for (int y = y0; y < y1; ++y) {
        for (int x = 0; x < out.width; ++x) {
            const std::size_t i = static_cast<std::size_t>(y) * out.width + x;
            const float d = log_depth[i];
            if (d == kNoDepth) continue;
            const float response = edl_response(log_depth, out.width, out.height, x, y, s.edl_radius_px, d);
            if (response > 0.0f) out.pixels[i] = darken(out.pixels[i], std::exp(-k * response));
        }
    }
}

// Runs fn(y0, y1) over bands of rows on the pool.
template <typename Fn>
void for_row_bands(int height, ThreadPool& pool, Fn&& fn) {
    const std::size_t bands = static_cast<std::size_t>((height + kRowsPerJob - 1) / kRowsPerJob);
    pool.for_each(bands, [&](std::size_t b) {
        const int y0 = static_cast<int>(b) * kRowsPerJob;
        fn(y0, std::min(height, y0 + kRowsPerJob));
    });
}

}  // namespace

RgbaImage resolve(const Framebuffer& fb, const ResolveSettings& settings, ThreadPool& pool) {
    if (!(settings.edl_strength >= 0.0f) || settings.edl_radius_px < 1) {
        throw Error::in_stage("resolve", "EDL strength must be >= 0 and the EDL radius >= 1 pixel");
    }
    RgbaImage out{fb.width(), fb.height(), {}};
    out.pixels.resize(static_cast<std::size_t>(fb.width()) * fb.height());
    for_row_bands(fb.height(), pool, [&](int y0, int y1) { copy_rows(fb, settings.background, y0, y1, out); });
    if (settings.edl_strength == 0.0f) return out;
    std::vector<float> log_depth(out.pixels.size());
    for_row_bands(fb.height(), pool, [&](int y0, int y1) { log_depth_rows(fb, y0, y1, log_depth); });
    for_row_bands(fb.height(), pool, [&](int y0, int y1) { edl_rows(log_depth, settings, y0, y1, out); });
    return out;
}

}  // namespace lidarscout::render
