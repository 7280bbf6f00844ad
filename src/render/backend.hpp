// Which rasterizer draws a frame: the CPU passes (always there, the default) or the CUDA
// plugin (liblidarscout_cuda_raster.so, used when it loads and a GPU is present), and the one
// function that draws a frame's passes (heightmaps, point layers, resolve) on either.
#pragma once

#include <cstddef>
#include <span>
#include <string>
#include <string_view>

#include "core/point_filter.hpp"
#include "core/thread_pool.hpp"
#include "render/camera.hpp"
#include "render/colour_modes.hpp"
#include "render/heightmap_pass.hpp"
#include "render/point_batch.hpp"
#include "render/resolve.hpp"

namespace lidarscout::render {

enum class Backend { Auto, Cpu, Cuda };

// "auto", "cpu", "cuda"; throws lidarscout::Error naming the known backends otherwise.
Backend parse_backend(std::string_view name);
std::string_view backend_name(Backend backend);

// Why the CUDA backend cannot draw here (no plugin, no GPU, ...); empty when it can. The
// plugin is opened and the GPU probed once per process.
std::string cuda_unavailable_reason();
// The GPU's name when the CUDA backend is available, else empty.
std::string cuda_device_name();

struct BackendChoice {
    Backend backend = Backend::Cpu;  // Cpu or Cuda
    std::string note;                // "CUDA backend unavailable: <reason>" when auto fell back
};

// What `requested` resolves to here: Cpu stays Cpu; Auto is Cuda when available, else Cpu
// with a note saying why; Cuda throws lidarscout::Error("CUDA backend unavailable: <reason>")
// when it is not available.
BackendChoice choose_backend(Backend requested);

// One layer of points drawn with one point size (chunk points, full-resolution points).
struct PointLayer {
    std::span<const PointBatch> batches;
    int point_size = 1;
    bool adaptive_size = false;  // PointPassSettings::adaptive_size
};

struct FrameSettings {
    ColourSettings colour;               // for heightmaps and points alike
    HeightmapPassSettings heightmaps;    // its colour settings are replaced by `colour`
    ResolveSettings resolve;
    std::size_t chunk_points = 50'000;   // points per work item (a CUDA thread block)
    PointFilter filter;                  // points of every layer it does not keep are not drawn
};

struct FrameImage {
    RgbaImage image;
    std::size_t drawn_pixels = 0;  // pixels where something was drawn (not background)
};

// Draws the heightmaps, then the point layers in order, and resolves, on `backend` (Auto is
// chosen as choose_backend does). Throws lidarscout::Error on bad sizes or settings (the same
// checks on both backends), and for Cuda when it is unavailable. Should the GPU fail during a
// frame, the frame is drawn on the CPU, the cause is printed once on stderr and the CUDA
// backend is not used again in this process.
FrameImage draw_frame(Backend backend, const Camera& camera, std::span<const HeightmapPatch> heightmaps,
                      std::span<const PointLayer> layers, const FrameSettings& settings, ThreadPool& pool);

}  // namespace lidarscout::render
