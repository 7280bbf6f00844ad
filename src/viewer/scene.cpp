// A frame's content and its drawing: overview points, colour settings, the passes and the resolve.
#include "viewer/scene.hpp"

#include <algorithm>
#include <set>

#include "render/framebuffer.hpp"
#include "render/point_pass.hpp"

namespace lidarscout::viewer {
namespace {

std::vector<render::PointBatch> all_batches(const Scene& scene) {
    auto out = batches_of(scene.chunk_points);
    const auto full = batches_of(scene.full_points);
    out.insert(out.end(), full.begin(), full.end());
    return out;
}

void draw_point_sets(render::Framebuffer& fb, const render::Camera& camera, std::span<const PointSet> sets,
                     const render::ColourSettings& colour, int point_size, ThreadPool& pool) {
    if (sets.empty()) return;
    render::PointPassSettings s;
    s.colour = colour;
    s.point_size = point_size;
    render::draw_points(fb, camera, batches_of(sets), s, pool);
}

std::size_t drawn_pixels(const render::Framebuffer& fb) {
    const std::size_t n = static_cast<std::size_t>(fb.width()) * fb.height();
    return n - static_cast<std::size_t>(std::count(fb.data(), fb.data() + n, render::kEmpty));
}

}  // namespace

std::vector<PointSet> overview_point_sets(const dataset::PatchGrid& grid, std::span<const dataset::CellKey> cells,
                                          std::span<const PatchHeightmap> heightmaps) {
    std::set<dataset::CellKey> covered;
    for (const auto& h : heightmaps) covered.insert(h.cell);
    std::vector<PointSet> out;
    for (const auto cell : cells) {
        if (!covered.contains(cell)) out.push_back(cell_point_set(grid, cell));
    }
    return out;
}

render::ColourSettings colour_settings(render::ColourMode mode, double z_min, double z_max) {
    render::ColourSettings c;
    c.mode = mode;
    if (z_min <= z_max) c.z_min = z_min, c.z_max = std::max(z_max, z_min + 1.0);
    return c;
}

RenderedScene render_scene(const Scene& scene, const render::Camera& camera, const SceneStyle& style,
                           ThreadPool& pool) {
    render::ColourSettings colour = style.colour;
    if (colour.mode == render::ColourMode::Intensity && style.auto_intensity) {
        const auto range = render::auto_intensity_range(all_batches(scene));
        colour.intensity_min = range[0], colour.intensity_max = std::max(range[1], range[0] + 1.0f);
    }
    render::Framebuffer fb(camera.width, camera.height);
    std::vector<render::HeightmapPatch> patches;
    patches.reserve(scene.heightmaps.size());
    for (const auto& h : scene.heightmaps) patches.push_back(h.view());
    render::HeightmapPassSettings hs = style.heightmaps;
    hs.colour = colour;
    if (!patches.empty()) render::draw_heightmaps(fb, camera, patches, hs, pool);
    draw_point_sets(fb, camera, scene.chunk_points, colour, style.chunk_point_size, pool);
    draw_point_sets(fb, camera, scene.full_points, colour, style.point_size, pool);
    return {render::resolve(fb, style.resolve, pool), drawn_pixels(fb)};
}

}  // namespace lidarscout::viewer
