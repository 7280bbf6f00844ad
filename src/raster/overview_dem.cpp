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
#include "core/patch_grid.hpp"
#include "nn/heightmap_network.hpp"
#include "recon/interpolation.hpp"

namespace lidarscout::raster {

float seam_weight(int row, int col, int size, int fade) {
    const int d = std::min({row, col, size - 1 - row, size - 1 - col});
    return fade <= 0 ? 1.0f : std::min(1.0f, static_cast<float>(d) / static_cast<float>(fade));
}

namespace {

// One patch on its way to the raster: the linear surface from a wide window (so that the
// triangles at the patch's border are those its neighbours see too) and, for cnn, the network's
// inputs and result on its own 96-texel window.
struct PatchJob {
    lidarscout::CellKey cell;
    recon::PatchPoints wide;
    recon::Triangulation triangulation;  // of `wide`
    recon::FaceMap face_map;
    recon::Image height, rgb;  // linear inside the real triangles (NaN outside), normalised heights
    recon::PatchPoints points;      // the network's window
    recon::InterpolatedPatch inputs;
    recon::Reconstruction network;

    bool ok() const { return wide.status == recon::PatchStatus::Ok; }
    bool has_network_inputs() const { return points.status == recon::PatchStatus::Ok; }
};

// At least half of the chunk points have a colour other than black (as eval decides).
bool grid_has_rgb(const lidarscout::PatchGrid& grid) {
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
std::vector<lidarscout::CellKey> candidate_blocks(const lidarscout::PatchGrid& grid, const DemGrid& dem) {
    std::set<lidarscout::CellKey> out;
    for (const auto& c : grid.cells()) {
        for (int dy = -1; dy <= 1; ++dy) {
            for (int dx = -1; dx <= 1; ++dx) {
                const lidarscout::CellKey k{c.ix + dx, c.iy + dy};
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
        const int n = kOverviewPatchTexels;
        const std::size_t texels = static_cast<std::size_t>(n) * n;
        std::vector<float> heights(texels, options_.nodata);
        std::vector<std::uint8_t> rgba(4 * texels, 0);
        const bool network = options_.network && job.has_network_inputs();
        for (int row = 0; row < n; ++row) {
            for (int col = 0; col < n; ++col) {
                const int wr = row + job.wide.spec.pad_texels, wc = col + job.wide.spec.pad_texels;
                if (job.face_map.at(wr, wc) < 0) continue;  // outside the chunk points' hull
                const std::size_t t = static_cast<std::size_t>(row) * n + col;
                const float w = network ? seam_weight(row, col, n, kSeamFadeTexels) : 0.0f;
                double h = job.wide.to_metres(job.height.at(wr, wc));
                if (network) h += correction(job, row, col) * w;
                heights[t] = static_cast<float>(h / outputs_.z_to_metres);
                if (outputs_.rgb) colour(job, row, col, w, network, rgba, t, texels);
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
    // The network's change to its own linear input, in metres.
    static double correction(const PatchJob& job, int row, int col) {
        const int pad = job.points.spec.pad_texels;
        const double linear = job.inputs.height_linear.at(row + pad, col + pad);
        return job.points.to_metres(job.network.height.at(row, col)) - job.points.to_metres(linear);
    }

    void colour(const PatchJob& job, int row, int col, float w, bool network, std::vector<std::uint8_t>& rgba,
                std::size_t t, std::size_t texels) const {
        const int wr = row + job.wide.spec.pad_texels, wc = col + job.wide.spec.pad_texels;
        const int pad = job.points.spec.pad_texels;
        for (int c = 0; c < 3; ++c) {
            float v = job.rgb.at(wr, wc, c);
            if (network && !job.network.rgb.empty()) {
                v += (job.network.rgb.at(row, col, c) - job.inputs.rgb_linear.at(row + pad, col + pad, c)) * w;
            }
            if (std::isnan(v)) return;
            rgba[c * texels + t] = static_cast<std::uint8_t>(std::lround(std::clamp(v, 0.0f, 1.0f) * 255.0f));
        }
        rgba[3 * texels + t] = 255;
    }

    const DemGrid& grid_;
    const OverviewDemOptions& options_;
    const DemOutputs& outputs_;
};

// The wide window's linear surface and, for the network, its inputs.
struct PatchSpecs {
    recon::PatchOptions wide, network;
};

void prepare(PatchJob& job, const lidarscout::PatchGrid& grid, const PatchSpecs& specs,
             const OverviewDemOptions& options) {
    std::vector<lidarscout::OverviewPoint> window = grid.window(job.cell, specs.wide.spec.pad_m());
    std::erase_if(window, [&](const lidarscout::OverviewPoint& p) {
        return !options.filter.keeps_class(p.classification) || !options.filter.keeps_intensity(p.intensity);
    });
    const double x0 = grid.cell_min_x(job.cell), y0 = grid.cell_min_y(job.cell);
    job.wide = recon::make_patch_points(window, x0, y0, specs.wide);
    if (!job.ok()) return;
    // Only the texels inside real triangles are kept, so no nearest-point map (most of the work
    // of recon's linear method) is needed.
    job.triangulation = recon::triangulate(job.wide);
    job.face_map = recon::build_face_map(job.triangulation, job.wide.size());
    job.height = recon::Image(job.wide.size(), 1);
    job.rgb = recon::Image(job.wide.size(), 3);
    recon::fill_linear(job.height, job.triangulation, job.face_map, recon::height_values(job.wide));
    recon::fill_linear(job.rgb, job.triangulation, job.face_map, recon::colour_values(job.wide));
    if (!options.network) return;
    job.points = recon::make_patch_points(window, x0, y0, specs.network);  // points beyond its window are ignored
    if (job.has_network_inputs()) job.inputs = recon::interpolate_patch(job.points);
}

void run_network(const nn::HeightmapNetwork& network, std::vector<PatchJob>& jobs, bool has_rgb) {
    std::vector<const recon::InterpolatedPatch*> batch;
    std::vector<PatchJob*> owners;
    for (auto& j : jobs) {
        if (!j.has_network_inputs()) continue;
        batch.push_back(&j.inputs);
        owners.push_back(&j);
    }
    if (batch.empty()) return;
    auto results = network.infer(batch, has_rgb, kOverviewPatchTexels);
    for (std::size_t i = 0; i < owners.size(); ++i) owners[i]->network = std::move(results.at(i));
}

}  // namespace

OverviewDemStats grid_overview_dem(const dataset::Dataset& ds, const DemGrid& grid, const OverviewDemOptions& options,
                                   const DemOutputs& outputs, ThreadPool& pool) {
    if (grid.block != kOverviewPatchTexels) {
        throw Error::in_stage("dem", "overview blocks must be 64 texels (internal error)");
    }
    const recon::PatchSpec spec{grid.texel_m, kOverviewPatchTexels, kLinearPadTexels};
    lidarscout::PatchGrid points(grid.origin_x, grid.origin_y, spec.patch_m());
    dataset::ChunkPointLoader loader(ds, points);
    loader.start();
    loader.wait();
    OverviewDemStats stats;
    stats.chunk_points = loader.loaded();
    stats.skipped = loader.errors();
    stats.chunk_points_skipped = loader.failed();
    const bool has_rgb = grid_has_rgb(points);
    const PatchSpecs specs{{spec, options.min_points, has_rgb},
                           {{grid.texel_m, kOverviewPatchTexels, 16}, options.min_points, has_rgb}};
    std::unique_ptr<nn::HeightmapNetwork> network;
    if (options.network) {
        const std::string path = options.model.empty() ? nn::default_model_path() : options.model;
        network =
            std::make_unique<nn::HeightmapNetwork>(nn::HeightmapNetwork::load(path, static_cast<int>(pool.size())));
    }
    const std::vector<lidarscout::CellKey> cells = candidate_blocks(points, grid);
    const PatchWriter writer(grid, options, outputs);
    const std::size_t group = 64;
    for (std::size_t first = 0; first < cells.size(); first += group) {
        std::vector<PatchJob> jobs(std::min(group, cells.size() - first));
        pool.for_each(jobs.size(), [&](std::size_t i) {
            jobs[i].cell = cells[first + i];
            prepare(jobs[i], points, specs, options);
        });
        std::erase_if(jobs, [&](const PatchJob& j) { return !j.ok(); });
        if (network) run_network(*network, jobs, has_rgb);
        for (const auto& j : jobs) writer.write(j);
        stats.patches_written += jobs.size();
        if (options.progress) options.progress(std::min(first + group, cells.size()), cells.size());
    }
    stats.patches_too_few = cells.size() - stats.patches_written;
    return stats;
}

}  // namespace lidarscout::raster
