// A frame's content and its drawing: overview points, colour settings, the passes and the resolve.
#include "viewer/scene.hpp"

#include <algorithm>
#include <set>

namespace lidarscout::viewer {
namespace {

// The colour settings of a frame: the intensity range from its points when asked for.
render::ColourSettings frame_colours(const SceneStyle& style, std::span<const render::PointBatch> chunk_points,
                                     std::span<const render::PointBatch> full_points) {
    render::ColourSettings colour = style.colour;
    if (colour.mode != render::ColourMode::Intensity || !style.auto_intensity) return colour;
    std::vector<render::PointBatch> all(chunk_points.begin(), chunk_points.end());
    all.insert(all.end(), full_points.begin(), full_points.end());
    const auto range = render::auto_intensity_range(all);
    colour.intensity_min = range[0], colour.intensity_max = std::max(range[1], range[0] + 1.0f);
    return colour;
}

}  // namespace

std::vector<PointSet> overview_point_sets(const lidarscout::PatchGrid& grid, std::span<const lidarscout::CellKey> cells,
                                          std::span<const PatchHeightmap> heightmaps) {
    std::set<lidarscout::CellKey> covered;
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

RenderedScene draw_scene_frame(const render::Camera& camera, std::span<const render::HeightmapPatch> heightmaps,
                               std::span<const render::PointBatch> chunk_points,
                               std::span<const render::PointBatch> full_points, const SceneStyle& style,
                               ThreadPool& pool) {
    render::FrameSettings settings;
    settings.colour = frame_colours(style, chunk_points, full_points);
    settings.heightmaps = style.heightmaps;
    settings.resolve = style.resolve;
    settings.filter = style.filter;
    const render::PointLayer layers[] = {{chunk_points, style.chunk_point_size},
                                         {full_points, style.point_size, style.adaptive_point_size}};
    auto frame = render::draw_frame(style.backend, camera, heightmaps, layers, settings, pool);
    return {std::move(frame.image), frame.drawn_pixels};
}

RenderedScene render_scene(const Scene& scene, const render::Camera& camera, const SceneStyle& style,
                           ThreadPool& pool) {
    std::vector<render::HeightmapPatch> patches;
    patches.reserve(scene.heightmaps.size());
    const Surface wanted = surface_of(style.filter);
    for (const auto& h : scene.heightmaps) patches.push_back(h.view(wanted));
    return draw_scene_frame(camera, patches, batches_of(scene.chunk_points), batches_of(scene.full_points), style,
                            pool);
}

}  // namespace lidarscout::viewer
