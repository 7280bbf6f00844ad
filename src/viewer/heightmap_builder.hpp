// The heightmap stage over many patches: the linear method spread over a thread pool, or the
// network in batches (the windows' interpolated inputs built in parallel, then one inference
// call per batch). Patches with too few chunk points get no heightmap (they keep showing their
// chunk points); heightmaps are masked to the tiles' footprints.
#pragma once

#include <cstddef>
#include <functional>
#include <span>
#include <vector>

#include "core/thread_pool.hpp"
#include "dataset/dataset.hpp"
#include "core/patch_grid.hpp"
#include "recon/patch_space.hpp"
#include "viewer/patch_heightmap.hpp"

namespace lidarscout::nn {
class HeightmapNetwork;
}

namespace lidarscout::viewer {

// The chunk points a window needs before the viewer draws a heightmap for it. Far lower than
// the reconstruction stage's 25 (recon::PatchOptions, what the network was trained on): a
// coarse surface from a handful of chunk points shows the terrain better than a handful of
// dots, and small or thinly chunked surveys (ky-woodford-county: 21 chunk points for its whole
// 0.35 km^2 tile) would otherwise never get one; more than the 3 a triangle needs, so that a
// window's few stray points do not make a surface.
inline constexpr std::size_t kViewerMinPoints = 6;

struct HeightmapBuildOptions {
    recon::PatchOptions patch{recon::PatchSpec{}, kViewerMinPoints, true};
    Footprints footprints;  // xy boxes of the data (tiles); empty = no mask
    std::size_t batch = 16;                   // patches per network call
    // Called after each patch (or batch) with the number of patches finished; any thread.
    std::function<void(std::size_t)> progress;
};

// The footprints of the dataset's tiles (their header bounds in metres).
std::vector<dataset::Bounds> tile_footprints(const dataset::Dataset& dataset);

// Whether the survey has colour: at least half of the grid's chunk points are not black
// (point formats without RGB load as black).
bool chunk_points_have_rgb(const lidarscout::PatchGrid& grid);

// Heightmaps of `cells` by the linear method, in the order of `cells` (those with too few
// points, or masked away entirely, left out).
std::vector<PatchHeightmap> build_linear_heightmaps(const lidarscout::PatchGrid& grid,
                                                    std::span<const lidarscout::CellKey> cells,
                                                    const HeightmapBuildOptions& options, ThreadPool& pool);

// The same by the network (64 x 64 patches from the 96 x 96 interpolated windows).
std::vector<PatchHeightmap> build_cnn_heightmaps(const lidarscout::PatchGrid& grid,
                                                 std::span<const lidarscout::CellKey> cells,
                                                 const nn::HeightmapNetwork& network,
                                                 const HeightmapBuildOptions& options, ThreadPool& pool);

}  // namespace lidarscout::viewer
