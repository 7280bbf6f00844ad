// DEMs from the overview alone (`lidarscout dem --from overview`): the chunk points of every
// tile (one small read each, no decompression) are binned into a patch grid on the DEM's
// lattice, then every 64 x 64-texel patch with enough chunk points in its window is
// reconstructed — in parallel, a group of patches at a time, so memory stays bounded — by:
//   linear  barycentric interpolation in the Delaunay triangles of the chunk points of a wide
//           window (the patch and 64 texels around it): a texel depends only on the triangle
//           that holds it, and with that margin neighbouring patches see the same triangles at
//           their common border (with the network's 16-texel padding they do not where chunk
//           points are sparse, and seams show), so patches join without seams;
//   cnn     the heightmap network (nn/) on its 96 x 96 window, run in batches; its change to
//           its own linear input is added to the wide linear surface, faded out over the 8
//           texels next to a patch border, so patches join on the (seamless) linear surface.
// Texels outside every real triangle (beyond the hull of the chunk points) are nodata: the
// overview says nothing there. Colour (the orthophoto) comes from the same method.
#pragma once

#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "core/error.hpp"
#include "raster/dem_grid.hpp"
#include "raster/full_dem.hpp"  // DemOutputs, PointFilter (and the declarations of ThreadPool, Dataset)

namespace lidarscout::raster {

inline constexpr int kOverviewPatchTexels = 64;  // the network's patch
inline constexpr int kSeamFadeTexels = 8;
inline constexpr int kLinearPadTexels = 64;

struct OverviewDemOptions {
    bool network = false;  // cnn instead of linear
    std::string model;     // empty: the shipped model
    // Chunk points it does not keep by class and intensity are left out (they have no returns).
    PointFilter filter;
    std::size_t min_points = 6;
    float nodata = -9999.0f;
    std::function<void(std::uint64_t, std::uint64_t)> progress;  // (patches done, total)
};

struct OverviewDemStats {
    std::uint64_t chunk_points = 0;
    std::vector<ErrorRecord> skipped;  // chunk points (or tiles) that could not be read, left out
    std::uint64_t chunk_points_skipped = 0;
    std::size_t patches_written = 0, patches_too_few = 0;
};

// `grid.block` must be kOverviewPatchTexels.
OverviewDemStats grid_overview_dem(const dataset::Dataset& dataset, const DemGrid& grid,
                                   const OverviewDemOptions& options, const DemOutputs& outputs, ThreadPool& pool);

// The weight of the network's correction at texel (row, col) of a size x size patch: 0 on the
// border texels, rising linearly to 1 at `fade` texels inside.
float seam_weight(int row, int col, int size, int fade);

}  // namespace lidarscout::raster
