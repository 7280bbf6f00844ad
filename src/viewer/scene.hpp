// A frame's content and how it is drawn: the heightmaps of the patches that have one, the
// chunk points of the visible patches that do not, and the full-resolution points of the
// tiles decoded so far; render_scene runs the heightmap pass, the point passes and the
// resolve, as the interactive viewer does every frame.
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include "core/patch_grid.hpp"
#include "core/point_filter.hpp"
#include "core/thread_pool.hpp"
#include "render/backend.hpp"
#include "render/camera.hpp"
#include "render/colour_modes.hpp"
#include "render/heightmap_pass.hpp"
#include "render/resolve.hpp"
#include "viewer/patch_heightmap.hpp"
#include "viewer/point_sets.hpp"

namespace lidarscout::viewer {

struct Scene {
    std::vector<PatchHeightmap> heightmaps;
    std::vector<PointSet> chunk_points;  // per visible cell without a heightmap
    std::vector<PointSet> full_points;   // per tile decoded at full resolution
};

// The chunk points of those `cells` that have no heightmap among `heightmaps`, one set per cell.
std::vector<PointSet> overview_point_sets(const lidarscout::PatchGrid& grid, std::span<const lidarscout::CellKey> cells,
                                          std::span<const PatchHeightmap> heightmaps);

struct SceneStyle {
    render::ColourSettings colour;
    bool auto_intensity = true;     // intensity range from the scene's points (2nd-98th percentile)
    int chunk_point_size = 2;       // pixels: chunk points are sparse, a bigger square reads better
    int point_size = 1;             // pixels: full-resolution points (the smallest, with an adaptive size)
    // Full-resolution points at least as wide as their spacing on screen (render::PointPassSettings),
    // so that near the camera they meet instead of showing the heightmap between them.
    bool adaptive_point_size = true;
    double lod_spacing_px = 1.0;    // LOD blocks: the level whose spacing is at most this many pixels (0: all points)
    render::HeightmapPassSettings heightmaps;  // its colour settings are replaced by `colour`
    render::ResolveSettings resolve;           // background, eye-dome lighting
    render::Backend backend = render::Backend::Cpu;  // the rasterizer (render/backend.hpp)
    // The points drawn (every layer); a bare-earth filter (surface_of) also tints the heightmaps
    // that do not show its surface yet (PatchHeightmap::view).
    PointFilter filter;
};

// Elevation colours over [z_min, z_max] (e.g. the dataset's range; widened when empty).
render::ColourSettings colour_settings(render::ColourMode mode, double z_min, double z_max);

struct RenderedScene {
    render::RgbaImage image;
    std::size_t drawn_pixels = 0;  // pixels where something was drawn (not background)
};

// Draws one frame on style.backend: the heightmaps (pushed back by their depth bias), then the
// chunk points and the full-resolution points, then the resolve. Both render_scene and
// render_snapshot draw through this.
RenderedScene draw_scene_frame(const render::Camera& camera, std::span<const render::HeightmapPatch> heightmaps,
                               std::span<const render::PointBatch> chunk_points,
                               std::span<const render::PointBatch> full_points, const SceneStyle& style,
                               ThreadPool& pool);

// Draws the scene at `camera` (heightmaps first, pushed back by their depth bias, then the
// chunk points and the full-resolution points) and resolves it to an image.
RenderedScene render_scene(const Scene& scene, const render::Camera& camera, const SceneStyle& style,
                           ThreadPool& pool);

}  // namespace lidarscout::viewer
