// The point pass: chunked, multi-threaded projection of points with atomic-min writes.
#include "render/point_pass.hpp"

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "core/error.hpp"

namespace lidarscout::render {
namespace {

constexpr int kMaxPointSize = 64;

// Where a work item starts: a batch and a point in it. Item j draws from its start to item j + 1's, about
// chunk_points points over as many batches as they lie in (a country's view is 600,000 cells of a few points
// each: an item a batch had been 14 MB of items, fresh pages, every frame).
struct JobStart {
    std::size_t batch, point;
};

// The viewport and depth range of one frame, in float.
struct Target {
    Framebuffer* fb;
    float width, height, near_m, far_m;
};

// One functor per colour mode, so the mode is chosen once per chunk and not per point.
struct RgbColour {
    std::uint32_t operator()(const PointAttr& p) const { return pack_rgba(p.r, p.g, p.b); }
};
struct ElevationColour {
    Palette::ElevationMap map;
    std::uint32_t operator()(const PointAttr& p) const { return map(p.dz); }
};
struct IntensityColour {
    const Palette* palette;
    std::uint32_t operator()(const PointAttr& p) const { return palette->intensity(p.intensity); }
};
struct ClassColour {
    const Palette* palette;
    std::uint32_t operator()(const PointAttr& p) const { return palette->classification(p.classification); }
};

// Whether a point is drawn: every point, or those a filter keeps.
struct KeepAll {
    bool operator()(const PointAttr&) const { return true; }
};
struct KeepFiltered {
    const PointFilter* filter;
    bool operator()(const PointAttr& p) const { return filter->keeps_drawn(p.classification, p.returns, p.intensity); }
};

float row_dot(const std::array<float, 4>& row, const PointAttr& p) {
    return row[0] * p.dx + row[1] * p.dy + row[2] * p.dz + row[3];
}

// One pixel per point.
template <typename Colour, typename Keep>
void draw_single(const Target& t, const ScreenTransform& s, std::span<const PointAttr> points, Colour colour,
                 Keep keep) {
    for (const PointAttr& p : points) {
        if (!keep(p)) continue;
        const float w = row_dot(s.depth, p);
        if (!(w >= t.near_m && w <= t.far_m)) continue;
        const float inv = 1.0f / w;
        const float x = row_dot(s.sx, p) * inv, y = row_dot(s.sy, p) * inv;
        if (!(x >= 0.0f && x < t.width && y >= 0.0f && y < t.height)) continue;
        t.fb->write(static_cast<int>(x), static_cast<int>(y), w, colour(p));
    }
}

// A square per point, side_of(1 / depth) pixels wide (N): columns floor(x) - (N-1)/2 .. + N-1
// (likewise rows), clipped.
template <typename Colour, typename Keep, typename Side>
void draw_squares(const Target& t, const ScreenTransform& s, std::span<const PointAttr> points, Colour colour,
                  Keep keep, Side side_of) {
    const int last_x = t.fb->width() - 1, last_y = t.fb->height() - 1;
    for (const PointAttr& p : points) {
        if (!keep(p)) continue;
        const float w = row_dot(s.depth, p);
        if (!(w >= t.near_m && w <= t.far_m)) continue;
        const float inv = 1.0f / w;
        const float x = row_dot(s.sx, p) * inv, y = row_dot(s.sy, p) * inv;
        const int side = side_of(inv);
        const auto margin = static_cast<float>(side);
        if (!(x >= -margin && x < t.width + margin && y >= -margin && y < t.height + margin)) continue;
        const int half = (side - 1) / 2;
        const int x0 = static_cast<int>(std::floor(x)) - half, y0 = static_cast<int>(std::floor(y)) - half;
        const std::uint64_t value = pack_fragment(w, colour(p));
        for (int py = std::max(y0, 0); py <= std::min(y0 + side - 1, last_y); ++py) {
            for (int px = std::max(x0, 0); px <= std::min(x0 + side - 1, last_x); ++px) {
                t.fb->write_packed(px, py, value);
            }
        }
    }
}

// `scale` > 0: adaptive sizes, ceil(scale / depth) within [size, kMaxAdaptivePointSize] (spacing on
// screen); else `size` for every point.
template <typename Colour, typename Keep>
void draw_chunk(const Target& t, const ScreenTransform& s, std::span<const PointAttr> points, Colour colour,
                Keep keep, int size, float scale) {
    if (scale > 0.0f) {
        const auto smallest = static_cast<float>(size), largest = static_cast<float>(kMaxAdaptivePointSize);
        draw_squares(t, s, points, colour, keep, [=](float inv_depth) {
            return static_cast<int>(std::clamp(std::ceil(scale * inv_depth), smallest, largest));
        });
    } else if (size == 1) {
        draw_single(t, s, points, colour, keep);
    } else {
        draw_squares(t, s, points, colour, keep, [size](float) { return size; });
    }
}

// The filter chosen once per chunk, like the colour mode: no test per point without one.
template <typename Colour>
void draw_chunk(const Target& t, const ScreenTransform& s, std::span<const PointAttr> points, Colour colour,
                const PointFilter& filter, int size, float scale) {
    if (filter.keeps_everything()) draw_chunk(t, s, points, colour, KeepAll{}, size, scale);
    else draw_chunk(t, s, points, colour, KeepFiltered{&filter}, size, scale);
}

// The items' starts, then the end ({batches.size(), 0}).
std::vector<JobStart> job_starts(std::span<const PointBatch> batches, std::size_t chunk_points) {
    std::vector<JobStart> starts;
    std::size_t in_item = chunk_points;  // points in the item being filled (full: the next point starts one)
    for (std::size_t b = 0; b < batches.size(); ++b) {
        const std::size_t n = batches[b].points.size();
        for (std::size_t p = 0; p < n;) {
            if (in_item == chunk_points) starts.push_back({b, p}), in_item = 0;
            const std::size_t take = std::min(n - p, chunk_points - in_item);
            p += take, in_item += take;
        }
    }
    starts.push_back({batches.size(), 0});
    return starts;
}

void check_settings(const Framebuffer& fb, const Camera& camera, const PointPassSettings& settings) {
    fb.check_size(camera.width, camera.height, "point pass");
    if (settings.point_size < 1 || settings.point_size > kMaxPointSize) {
        throw Error("point pass: point size " + std::to_string(settings.point_size) + " is not within 1.." +
                    std::to_string(kMaxPointSize));
    }
}

}  // namespace

float adaptive_scale(const PointPassSettings& settings, const PointBatch& batch, const Camera& camera) {
    if (!settings.adaptive_size || !(batch.spacing_m > 0.0f)) return 0.0f;
    return static_cast<float>(batch.spacing_m * camera.focal_px());
}

void draw_points(Framebuffer& fb, const Camera& camera, std::span<const PointBatch> batches,
                 const PointPassSettings& settings, ThreadPool& pool) {
    check_settings(fb, camera, settings);
    const Palette palette(settings.colour);
    const Target target{&fb, static_cast<float>(fb.width()), static_cast<float>(fb.height()),
                        static_cast<float>(camera.near_m), static_cast<float>(camera.far_m)};
    const auto draw_piece = [&](const PointBatch& batch, std::size_t begin, std::size_t end) {
        const auto points = batch.points.subspan(begin, end - begin);
        const ScreenTransform s = camera.screen_transform(batch.origin_x, batch.origin_y, batch.origin_z);
        const int size = settings.point_size;
        const float scale = adaptive_scale(settings, batch, camera);
        const PointFilter& filter = settings.filter;
        switch (palette.mode()) {
            case ColourMode::Rgb: return draw_chunk(target, s, points, RgbColour{}, filter, size, scale);
            case ColourMode::Elevation:
                return draw_chunk(target, s, points, ElevationColour{palette.elevation_map(batch.origin_z)}, filter,
                                  size, scale);
            case ColourMode::Intensity:
                return draw_chunk(target, s, points, IntensityColour{&palette}, filter, size, scale);
            case ColourMode::Classification:
                return draw_chunk(target, s, points, ClassColour{&palette}, filter, size, scale);
        }
    };
    const std::vector<JobStart> starts = job_starts(batches, std::max<std::size_t>(1, settings.chunk_points));
    pool.for_each(starts.size() - 1, [&](std::size_t j) {
        const JobStart from = starts[j], to = starts[j + 1];
        for (std::size_t b = from.batch; b <= to.batch && b < batches.size(); ++b) {
            const std::size_t begin = b == from.batch ? from.point : 0;
            const std::size_t end = b == to.batch ? to.point : batches[b].points.size();
            if (begin < end) draw_piece(batches[b], begin, end);
        }
    });
}

}  // namespace lidarscout::render
