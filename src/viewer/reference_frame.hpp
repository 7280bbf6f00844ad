// The all-points reference frame of a view for any size of dataset: every point of every tile
// the camera sees (screen coverage above zero, the tiles the residency wants), decoded in pieces
// (point_sets.hpp) and drawn into one framebuffer as each piece arrives, over the heightmaps
// given, then resolved as a frame is. Only the pieces being decoded are held, never all points:
// a country seen whole takes minutes, not its size in memory. The picture equals drawing every
// point at once (the point pass's atomic min does not depend on order). Colours are the style's
// (no automatic intensity range: the points are never all at hand); surveys without colour are
// grey as the scheduler paints them.
// The reference is cached on disk, keyed by the dataset (every tile's path, size and point
// count), the camera, the image size and the style, so that it is built once.
#pragma once

#include <cstdint>
#include <filesystem>
#include <functional>
#include <optional>
#include <span>
#include <string>

#include "core/thread_pool.hpp"
#include "dataset/dataset.hpp"
#include "render/camera.hpp"
#include "render/heightmap_pass.hpp"
#include "render/resolve.hpp"
#include "viewer/scene.hpp"

namespace lidarscout::viewer {

// Points decoded and drawn so far, of all the visible tiles hold.
using ReferenceProgress = std::function<void(std::uint64_t points_done, std::uint64_t points_total)>;

// The reference frame of `camera` (see above), on the CPU. Throws lidarscout::Error when a
// visible tile cannot be decoded (a reference without some points would be wrong).
render::RgbaImage stream_reference_frame(const dataset::Dataset& ds, const render::Camera& camera,
                                         std::span<const render::HeightmapPatch> heightmaps, const SceneStyle& style,
                                         ThreadPool& pool, const ReferenceProgress& progress = {});

// The cache key of that frame (hex): the dataset's tiles, the camera, the style; `extra` for
// what else it depends on (how its heightmaps were made).
std::string reference_key(const dataset::Dataset& ds, const render::Camera& camera, const SceneStyle& style,
                          const std::string& extra = {});

// The frame cached under `key` in `dir`; nullopt when there is none (or it is unreadable).
std::optional<render::RgbaImage> load_reference(const std::filesystem::path& dir, const std::string& key);
// Caches `image` under `key` in `dir` (created when missing; written under a temporary name and renamed).
void store_reference(const std::filesystem::path& dir, const std::string& key, const render::RgbaImage& image);

}  // namespace lidarscout::viewer
