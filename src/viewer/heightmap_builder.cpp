// The heightmap stage over many patches: linear in parallel, the network in batches.
#include "viewer/heightmap_builder.hpp"

#include <algorithm>
#include <optional>

#include "nn/heightmap_network.hpp"
#include "recon/interpolation.hpp"

namespace lidarscout::viewer {
namespace {

// Keeps the heightmaps that exist and still have texels after masking, in order.
std::vector<PatchHeightmap> finish(std::vector<std::optional<PatchHeightmap>>& built,
                                   const HeightmapBuildOptions& options) {
    std::vector<PatchHeightmap> out;
    for (auto& h : built) {
        if (!h) continue;
        if (!options.footprints.empty() && !mask_to_footprints(*h, options.footprints)) continue;
        out.push_back(std::move(*h));
    }
    return out;
}

// One batch of the network: the windows' points and interpolated inputs built in parallel,
// then one inference for those with enough points.
void run_cnn_batch(const lidarscout::PatchGrid& grid, std::span<const lidarscout::CellKey> cells,
                   const nn::HeightmapNetwork& network, const HeightmapBuildOptions& options, ThreadPool& pool,
                   std::span<std::optional<PatchHeightmap>> out) {
    std::vector<recon::PatchPoints> points(cells.size());
    std::vector<recon::InterpolatedPatch> inputs(cells.size());
    pool.for_each(cells.size(), [&](std::size_t i) {
        points[i] = recon::make_patch_points(grid, cells[i], options.patch);
        if (points[i].status == recon::PatchStatus::Ok) inputs[i] = recon::interpolate_patch(points[i]);
    });
    std::vector<const recon::InterpolatedPatch*> ready;
    std::vector<std::size_t> index;
    for (std::size_t i = 0; i < cells.size(); ++i) {
        if (points[i].status != recon::PatchStatus::Ok) continue;
        ready.push_back(&inputs[i]);
        index.push_back(i);
    }
    if (ready.empty()) return;
    const auto results = network.infer(ready, options.patch.has_rgb, options.patch.spec.patch_texels);
    for (std::size_t k = 0; k < results.size(); ++k) {
        const std::size_t i = index[k];
        out[i] = heightmap_from_reconstruction(cells[i], points[i], results[k]);
    }
}

}  // namespace

std::vector<dataset::Bounds> tile_footprints(const dataset::Dataset& dataset) {
    std::vector<dataset::Bounds> out;
    out.reserve(dataset.tiles.size());
    for (const auto& t : dataset.tiles) out.push_back(t.bounds_m);
    return out;
}

bool chunk_points_have_rgb(const lidarscout::PatchGrid& grid) {
    std::size_t coloured = 0, total = 0;
    for (const auto cell : grid.cells()) {
        for (const auto& p : grid.points_in(cell)) {
            coloured += (p.rgb.r | p.rgb.g | p.rgb.b) != 0;
            ++total;
        }
    }
    return coloured > 0 && coloured * 2 >= total;
}

std::vector<PatchHeightmap> build_linear_heightmaps(const lidarscout::PatchGrid& grid,
                                                    std::span<const lidarscout::CellKey> cells,
                                                    const HeightmapBuildOptions& options, ThreadPool& pool) {
    std::vector<std::optional<PatchHeightmap>> built(cells.size());
    pool.for_each(cells.size(), [&](std::size_t i) {
        built[i] = linear_heightmap(grid, cells[i], options.patch);
        if (options.progress) options.progress(1);
    });
    return finish(built, options);
}

std::vector<PatchHeightmap> build_cnn_heightmaps(const lidarscout::PatchGrid& grid,
                                                 std::span<const lidarscout::CellKey> cells,
                                                 const nn::HeightmapNetwork& network,
                                                 const HeightmapBuildOptions& options, ThreadPool& pool) {
    std::vector<std::optional<PatchHeightmap>> built(cells.size());
    const std::size_t batch = std::max<std::size_t>(1, options.batch);
    for (std::size_t first = 0; first < cells.size(); first += batch) {
        const std::size_t n = std::min(batch, cells.size() - first);
        run_cnn_batch(grid, cells.subspan(first, n), network, options, pool, std::span(built).subspan(first, n));
        if (options.progress) options.progress(n);
    }
    return finish(built, options);
}

}  // namespace lidarscout::viewer
