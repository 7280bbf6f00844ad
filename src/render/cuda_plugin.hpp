// Finding and opening liblidarscout_cuda_raster.so, the CUDA rasterizer plugin
// (render/cuda/raster_abi.h), and drawing a frame with it. Looked for, in order:
// $LIDARSCOUT_CUDA_RASTER (a file), next to the running program, in ../lib/lidarscout/ beside
// it, and in the build folder this program was built in.
#pragma once

#include <span>
#include <string>
#include <vector>

#include "render/backend.hpp"

namespace lidarscout::render::cuda {

inline constexpr char kPluginFileName[] = "liblidarscout_cuda_raster.so";

// Candidate paths of the plugin, in the order above.
std::vector<std::string> plugin_candidates();

// Opens the plugin and the GPU once per process; empty when usable, else why not.
std::string unavailable_reason();
std::string device_name();

// Draws a frame on the GPU (the caller has checked the settings). Throws lidarscout::Error
// when the plugin is unavailable or the GPU reports an error.
FrameImage draw_frame(const Camera& camera, std::span<const HeightmapPatch> heightmaps,
                      std::span<const PointLayer> layers, const FrameSettings& settings);

}  // namespace lidarscout::render::cuda
