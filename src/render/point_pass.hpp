// The point pass: projects every point of a set of batches and writes it into the
// framebuffer with the atomic min (Schütz et al. 2022, as in the paper). The points are cut
// into chunks of `chunk_points` (one LAZ chunk, the paper's one thread block per chunk) and
// the chunks are spread over a thread pool. Per chunk the camera transform is rebuilt for the
// batch's origin (double subtraction, then float), so the per-point work is float only: one
// 3x4 transform, one division, a range test and an atomic min; no allocation, no virtual call.
// With an adaptive size, a point whose batch spacing is more than a pixel on screen (near the
// camera) is drawn as a square of that spacing, as Potree sizes its points: the surface between
// them is filled. Points a filter leaves out (class, return kind, intensity) are not drawn.
#pragma once

#include <cstddef>
#include <span>

#include "core/point_filter.hpp"
#include "core/thread_pool.hpp"
#include "render/camera.hpp"
#include "render/colour_modes.hpp"
#include "render/framebuffer.hpp"
#include "render/point_batch.hpp"

namespace lidarscout::render {

// The largest square an adaptive point size draws (pixels).
inline constexpr int kMaxAdaptivePointSize = 16;

struct PointPassSettings {
    int point_size = 1;                  // pixels: N > 1 draws an N x N square around the point
    // Each point of a batch with a spacing is drawn at least ceil(spacing_m * focal / depth)
    // pixels wide (its spacing on screen), at most kMaxAdaptivePointSize, so that near points
    // meet; point_size stays the minimum.
    bool adaptive_size = false;
    std::size_t chunk_points = 50'000;   // points per work item
    ColourSettings colour;
    PointFilter filter;  // points it does not keep are skipped (a point of unknown returns passes on returns)
};

// What an adaptive point's side is computed from: spacing_m x the focal length in pixels (its
// side is ceil(scale / depth)); 0 when the size is fixed (no adaptive size, or no spacing).
float adaptive_scale(const PointPassSettings& settings, const PointBatch& batch, const Camera& camera);

// Draws the batches into `fb` (whose size must be the camera's). Throws lidarscout::Error on a
// size mismatch, a point size outside 1..64, or bad colour settings.
void draw_points(Framebuffer& fb, const Camera& camera, std::span<const PointBatch> batches,
                 const PointPassSettings& settings, ThreadPool& pool);

}  // namespace lidarscout::render
