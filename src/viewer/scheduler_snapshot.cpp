// Drawing a scheduler snapshot: views into the shared heightmaps and point sets, drawn by
// draw_scene_frame (scene.hpp) as render_scene draws a Scene.
#include "viewer/scheduler_snapshot.hpp"

namespace lidarscout::viewer {
namespace {

std::vector<render::PointBatch> batches(const std::vector<std::shared_ptr<const PointSet>>& sets, bool on) {
    std::vector<render::PointBatch> out;
    if (!on) return out;
    out.reserve(sets.size());
    for (const auto& s : sets) out.push_back(s->batch());
    return out;
}

}  // namespace

RenderedScene render_snapshot(const SceneSnapshot& snapshot, const render::Camera& camera, const SceneStyle& style,
                              ThreadPool& pool, const SceneLayers& layers) {
    std::vector<render::HeightmapPatch> patches;
    if (layers.heightmaps) {
        patches.reserve(snapshot.heightmaps.size());
        for (const auto& h : snapshot.heightmaps) patches.push_back(h->view());
    }
    return draw_scene_frame(camera, patches, batches(snapshot.chunk_points, layers.chunk_points),
                            batches(snapshot.full_points, layers.full_points), style, pool);
}

}  // namespace lidarscout::viewer
