// Drawing a scheduler snapshot: views into the shared heightmaps, point sets and LOD blocks (at
// the level the camera needs), drawn by draw_scene_frame (scene.hpp) as render_scene draws a Scene.
#include "viewer/scene_snapshot.hpp"

namespace lidarscout::viewer {
namespace {

// The sets' batches into `out`, whose storage is kept between frames (a country's view is 600,000 cells: their
// batches are 33 MB, fresh pages every frame drawn had they been new), unless it is four times what they need.
void batches(const std::vector<std::shared_ptr<const PointSet>>& sets, bool on,
             std::vector<render::PointBatch>& out) {
    const std::size_t needed = on ? sets.size() : 0;
    if (out.capacity() > 4 * needed + 4096) out = {};
    out.clear();
    out.reserve(needed);
    for (std::size_t k = 0; k < needed; ++k) out.push_back(sets[k]->batch());
}

}  // namespace

RenderedScene render_snapshot(const SceneSnapshot& snapshot, const render::Camera& camera, const SceneStyle& style,
                              ThreadPool& pool, const SceneLayers& layers) {
    std::vector<render::HeightmapPatch> patches;
    if (layers.heightmaps) {
        patches.reserve(snapshot.heightmaps.size());
        const Surface wanted = surface_of(style.filter);
        for (const auto& h : snapshot.heightmaps) patches.push_back(h->view(wanted));
    }
    const auto full = layers.full_points ? lod_batches(snapshot.full_points, camera, style.lod_spacing_px)
                                         : std::vector<render::PointBatch>{};
    thread_local std::vector<render::PointBatch> chunk_batches;
    batches(snapshot.chunk_points, layers.chunk_points, chunk_batches);
    return draw_scene_frame(camera, patches, chunk_batches, full, style, pool);
}

std::array<std::uint64_t, 256> loaded_class_counts(const SceneSnapshot& snapshot) {
    std::array<std::uint64_t, 256> out{};
    for (const auto& block : snapshot.full_points) {
        for (const auto& [code, n] : block->points.class_counts) out[code] += n;
    }
    return out;
}

}  // namespace lidarscout::viewer
