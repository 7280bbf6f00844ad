// What the scheduler has ready for drawing at one moment, shared with the worker threads
// through shared_ptr so that taking it every frame copies pointers, never points or
// heightmaps; and its drawing with the renderer's passes, each layer optional.
#pragma once

#include <array>
#include <cstdint>
#include <memory>
#include <vector>

#include "core/thread_pool.hpp"
#include "render/camera.hpp"
#include "viewer/patch_heightmap.hpp"
#include "viewer/point_lod.hpp"
#include "viewer/point_sets.hpp"
#include "viewer/scene.hpp"

namespace lidarscout::viewer {

struct SceneSnapshot {
    std::vector<std::shared_ptr<const PatchHeightmap>> heightmaps;
    std::vector<std::shared_ptr<const PointSet>> chunk_points;  // cells without a heightmap
    LodBlocks full_points;  // LOD blocks of the tiles held (full or coarse levels)
    std::uint64_t version = 0;                                  // grows with every change
};

struct SceneLayers {
    bool heightmaps = true, chunk_points = true, full_points = true;
};

// Draws the layers of `snapshot` at `camera` as render_scene draws a Scene; of each LOD block
// the level for style.lod_spacing_px.
RenderedScene render_snapshot(const SceneSnapshot& snapshot, const render::Camera& camera, const SceneStyle& style,
                              ThreadPool& pool, const SceneLayers& layers = {});

// The full-resolution points held for the view, by class (the LOD blocks' counts: no point visited).
std::array<std::uint64_t, 256> loaded_class_counts(const SceneSnapshot& snapshot);

}  // namespace lidarscout::viewer
