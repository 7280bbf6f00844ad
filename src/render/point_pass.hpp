// The point pass: projects every point of a set of batches and writes it into the
// framebuffer with the atomic min (Schütz et al. 2022, as in the paper). The points are cut
// into chunks of `chunk_points` (one LAZ chunk, the paper's one thread block per chunk) and
// the chunks are spread over a thread pool. Per chunk the camera transform is rebuilt for the
// batch's origin (double subtraction, then float), so the per-point work is float only: one
// 3x4 transform, one division, a range test and an atomic min; no allocation, no virtual call.
#pragma once

#include <cstddef>
#include <span>

#include "core/thread_pool.hpp"
#include "render/camera.hpp"
#include "render/colour_modes.hpp"
#include "render/framebuffer.hpp"
#include "render/point_batch.hpp"

namespace lidarscout::render {

struct PointPassSettings {
    int point_size = 1;                  // pixels: N > 1 draws an N x N square around the point
    std::size_t chunk_points = 50'000;   // points per work item
    ColourSettings colour;
};

// Draws the batches into `fb` (whose size must be the camera's). Throws lidarscout::Error on a
// size mismatch, a point size outside 1..64, or bad colour settings.
void draw_points(Framebuffer& fb, const Camera& camera, std::span<const PointBatch> batches,
                 const PointPassSettings& settings, ThreadPool& pool);

}  // namespace lidarscout::render
