// Drawing a scheduler snapshot: the heightmap pass, the chunk and full-resolution point passes
// and the resolve, over views into the shared heightmaps and point sets.
#include "viewer/scheduler_snapshot.hpp"

#include <algorithm>

#include "render/framebuffer.hpp"
#include "render/point_pass.hpp"

namespace lidarscout::viewer {
namespace {

std::vector<render::PointBatch> batches(const std::vector<std::shared_ptr<const PointSet>>& sets, bool on) {
    std::vector<render::PointBatch> out;
    if (!on) return out;
    out.reserve(sets.size());
    for (const auto& s : sets) out.push_back(s->batch());
    return out;
}

void draw_batches(render::Framebuffer& fb, const render::Camera& camera, const std::vector<render::PointBatch>& b,
                  const render::ColourSettings& colour, int point_size, ThreadPool& pool) {
    if (b.empty()) return;
    render::PointPassSettings s;
    s.colour = colour;
    s.point_size = point_size;
    render::draw_points(fb, camera, b, s, pool);
}

}  // namespace

RenderedScene render_snapshot(const SceneSnapshot& snapshot, const render::Camera& camera, const SceneStyle& style,
                              ThreadPool& pool, const SceneLayers& layers) {
    const auto chunk = batches(snapshot.chunk_points, layers.chunk_points);
    const auto full = batches(snapshot.full_points, layers.full_points);
    render::ColourSettings colour = style.colour;
    if (colour.mode == render::ColourMode::Intensity && style.auto_intensity) {
        auto all = chunk;
        all.insert(all.end(), full.begin(), full.end());
        const auto range = render::auto_intensity_range(all);
        colour.intensity_min = range[0], colour.intensity_max = std::max(range[1], range[0] + 1.0f);
    }
    render::Framebuffer fb(camera.width, camera.height);
    if (layers.heightmaps && !snapshot.heightmaps.empty()) {
        std::vector<render::HeightmapPatch> patches;
        patches.reserve(snapshot.heightmaps.size());
        for (const auto& h : snapshot.heightmaps) patches.push_back(h->view());
        render::HeightmapPassSettings hs = style.heightmaps;
        hs.colour = colour;
        render::draw_heightmaps(fb, camera, patches, hs, pool);
    }
    draw_batches(fb, camera, chunk, colour, style.chunk_point_size, pool);
    draw_batches(fb, camera, full, colour, style.point_size, pool);
    const std::size_t n = static_cast<std::size_t>(fb.width()) * fb.height();
    const auto empty = static_cast<std::size_t>(std::count(fb.data(), fb.data() + n, render::kEmpty));
    return {render::resolve(fb, style.resolve, pool), n - empty};
}

}  // namespace lidarscout::viewer
