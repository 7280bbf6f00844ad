// grid_overview_dem: chunk points -> patch grid -> per patch linear (or network) -> blocks.
#include "raster/overview_dem.hpp"

#include <algorithm>
#include <cmath>
#include <memory>
#include <set>

#include "core/error.hpp"
#include "core/thread_pool.hpp"
#include "dataset/chunk_point_loader.hpp"
#include "dataset/dataset.hpp"
#include "dataset/patch_grid.hpp"
#include "nn/heightmap_network.hpp"
#include "recon/interpolation.hpp"

namespace lidarscout::raster {

float seam_weight(int row, int col, int size, int fade) {
    const int d = std::min({row, col, size - 1 - row, size - 1 - col});
    return fade <= 0 ? 1.0f : std::min(1.0f, static_cast<float>(d) / static_cast<float>(fade));
}

namespace {

// One patch on its way to the raster.
struct PatchJob {
    dataset::CellKey cell;
    recon::PatchPoints points;
    recon::InterpolatedPatch inputs;
    recon::Reconstruction network;  // cnn only
};

// At least half of the chunk points have a colour other than black (as eval decides).
bool grid_has_rgb(const dataset::PatchGrid& grid) {
    std::uint64_t coloured = 0, all = 0;
    for (const auto& cell : grid.cells()) {
        for (const auto& p : grid.points_in(cell)) {
            coloured += (p.rgb.r | p.rgb.g | p.rgb.b) != 0;
            ++all;
        }
    }
    return coloured > 0 && coloured * 2 >= all;
}

// Blocks whose window may hold chunk points: the cells with points and their neighbours.
std::vector<dataset::CellKey> candidate_blocks(const dataset::PatchGrid& grid, const DemGrid& dem) {
    std::set<dataset::CellKey> out;
    for (const auto& c : grid.cells()) {
        for (int dy = -1; dy <= 1; ++dy) {
            for (int dx = -1; dx <= 1; ++dx) {
                const dataset::CellKey k{c.ix + dx, c.iy + dy};
                if (k.ix >= 0 && k.iy >= 0 && k.ix < dem.blocks_x() && k.iy < dem.blocks_y()) out.insert(k);
            }
        }
    }
    return {out.begin(), out.end()};
}

class PatchWriter {
public:
    PatchWriter(const DemGrid& grid, const OverviewDemOptions& options, const DemOutputs& outputs)
        : grid_(grid), options_(options), outputs_(outputs) {}

    void write(const PatchJob& job) const {
        const int n = kOverviewPatchTexels, pad = job.points.spec.pad_texels;
        const recon::Image linear = recon::crop_centre(job.inputs.height_linear, n);
        const std::size_t texels = static_cast<std::size_t>(n) * n;
        std::vector<float> heights(texels, options_.nodata);
        std::vector<std::uint8_t> rgba(4 * texels, 0);
        for (int row = 0; row < n; ++row) {
            for (int col = 0; col < n; ++col) {
                if (job.inputs.face_map.at(row + pad, col + pad) < 0) continue;  // outside the chunk points' hull
                const std::size_t t = static_cast<std::size_t>(row) * n + col;
                float h = linear.at(row, col);
                if (options_.network) h += (job.network.height.at(row, col) - h) * seam_weight(row, col, n, kSeamFadeTexels);
                heights[t] = static_cast<float>(job.points.to_metres(h) / outputs_.z_to_metres);
                if (outputs_.rgb) colour(job, row, col, rgba, t, texels);
            }
        }
        write_block(*outputs_.heights, grid_, 1, job.cell.ix, job.cell.iy, std::span<const float>(heights));
        if (!outputs_.rgb) return;
        for (int band = 0; band < 4; ++band) {
            write_block(*outputs_.rgb, grid_, band + 1, job.cell.ix, job.cell.iy,
                        std::span<const std::uint8_t>(rgba.data() + band * texels, texels));
        }
    }

private:
    void colour(const PatchJob& job, int row, int col, std::vector<std::uint8_t>& rgba, std::size_t t,
                std::size_t texels) const {
        const int pad = job.points.spec.pad_texels;
        const float w = options_.network ? seam_weight(row, col, kOverviewPatchTexels, kSeamFadeTexels) : 0.0f;
        for (int c = 0; c < 3; ++c) {
            float v = job.inputs.rgb_linear.at(row + pad, col + pad, c);
            if (options_.network && !job.network.rgb.empty()) v += (job.network.rgb.at(row, col, c) - v) * w;
            if (std::isnan(v)) return;
            rgba[c * texels + t] = static_cast<std::uint8_t>(std::lround(std::clamp(v, 0.0f, 1.0f) * 255.0f));
        }
        rgba[3 * texels + t] = 255;
    }

    const DemGrid& grid_;
    const OverviewDemOptions& options_;
    const DemOutputs& outputs_;
};

void prepare(PatchJob& job, const dataset::PatchGrid& grid, const recon::PatchOptions& patch, const ClassFilter& classes) {
    std::vector<dataset::OverviewPoint> window = grid.window(job.cell, patch.spec.pad_m());
    std::erase_if(window, [&](const dataset::OverviewPoint& p) { return !classes.keep[p.classification]; });
    job.points = recon::make_patch_points(window, grid.cell_min_x(job.cell), grid.cell_min_y(job.cell), patch);
    if (job.points.status == recon::PatchStatus::Ok) job.inputs = recon::interpolate_patch(job.points);
}

}  // namespace

OverviewDemStats grid_overview_dem(const dataset::Dataset& ds, const DemGrid& grid, const OverviewDemOptions& options,
                                   const DemOutputs& outputs, ThreadPool& pool) {
    if (grid.block != kOverviewPatchTexels) throw Error::in_stage("dem", "overview blocks must be 64 texels (internal error)");
    const recon::PatchSpec spec{grid.texel_m, kOverviewPatchTexels, 16};
    dataset::PatchGrid points(grid.origin_x, grid.origin_y, spec.patch_m());
    dataset::ChunkPointLoader loader(ds, points);
    loader.start();
    loader.wait();
    OverviewDemStats stats;
    stats.chunk_points = loader.loaded();
    const recon::PatchOptions patch{spec, options.min_points, grid_has_rgb(points)};
    std::unique_ptr<nn::HeightmapNetwork> network;
    if (options.network) {
        const std::string path = options.model.empty() ? nn::default_model_path() : options.model;
        network = std::make_unique<nn::HeightmapNetwork>(nn::HeightmapNetwork::load(path, static_cast<int>(pool.size())));
    }
    const std::vector<dataset::CellKey> cells = candidate_blocks(points, grid);
    const PatchWriter writer(grid, options, outputs);
    const std::size_t group = 64;
    for (std::size_t first = 0; first < cells.size(); first += group) {
        std::vector<PatchJob> jobs(std::min(group, cells.size() - first));
        pool.for_each(jobs.size(), [&](std::size_t i) {
            jobs[i].cell = cells[first + i];
            prepare(jobs[i], points, patch, options.classes);
        });
        std::erase_if(jobs, [&](const PatchJob& j) { return j.points.status != recon::PatchStatus::Ok; });
        if (network && !jobs.empty()) {
            std::vector<const recon::InterpolatedPatch*> batch;
            for (const auto& j : jobs) batch.push_back(&j.inputs);
            auto results = network->infer(batch, patch.has_rgb, kOverviewPatchTexels);
            for (std::size_t i = 0; i < jobs.size(); ++i) jobs[i].network = std::move(results.at(i));
        }
        for (const auto& j : jobs) writer.write(j);
        stats.patches_written += jobs.size();
        if (options.progress) options.progress(std::min(first + group, cells.size()), cells.size());
    }
    stats.patches_too_few = cells.size() - stats.patches_written;
    return stats;
}

}  // namespace lidarscout::raster
