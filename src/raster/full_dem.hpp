// DEMs from every point (`lidarscout dem --from full`): tiles are streamed one at a time in
// south-to-north order (LAZ chunks decoded in parallel), each point of the chosen classes is
// added to its texel (recon/texel_stats.hpp: the same gridding as `eval`'s ground truth, so
// `--method mean` equals it texel by texel), and a block is finished — its statistic computed,
// written, freed — as soon as the last tile that overlaps it is done. Memory is therefore the
// blocks under the tiles in flight, not the raster. A point outside its tile's header bounds
// (beyond a texel) is an error naming the file: its block may already be written.
#pragma once

#include <array>
#include <cstdint>
#include <functional>

#include "raster/dem_grid.hpp"
#include "recon/texel_stats.hpp"

namespace lidarscout {
class ThreadPool;
}
namespace lidarscout::dataset {
struct Dataset;
}

namespace lidarscout::raster {

// Which ASPRS classes count: all by default.
struct ClassFilter {
    std::array<bool, 256> keep;
    ClassFilter() { keep.fill(true); }
    // Only the listed classes (an empty list keeps all).
    static ClassFilter only(const std::vector<int>& classes);
};

struct FullDemOptions {
    recon::TexelStatistic statistic = recon::TexelStatistic::Mean;
    ClassFilter classes;
    float nodata = -9999.0f;
    // Called after each batch of points: (points done, points total).
    std::function<void(std::uint64_t, std::uint64_t)> progress;
};

// Where the finished blocks go: heights (band 1, the frame's vertical unit) and, when `rgb` is
// set, colour (bands 1-3) with alpha (band 4, 255 where a point fell).
struct DemOutputs {
    BlockRaster* heights = nullptr;
    BlockRaster* rgb = nullptr;
    double z_to_metres = 1.0;  // heights are written in metres / z_to_metres
};

struct FullDemStats {
    std::uint64_t points_read = 0, points_used = 0;
    std::size_t blocks_written = 0;
    std::size_t peak_blocks = 0;  // blocks held at once
};

FullDemStats grid_full_dem(const dataset::Dataset& dataset, const DemGrid& grid, const FullDemOptions& options,
                           const DemOutputs& outputs, ThreadPool& pool);

// One block's height image (block x block, rows from the south) of the statistic, in
// metres / z_to_metres, `nodata` where no point fell; and its RGBA planes (4 x block x block).
std::vector<float> block_heights(std::span<const recon::TexelStats> texels, recon::TexelStatistic statistic,
                                 double z_to_metres, float nodata);
std::vector<std::uint8_t> block_rgba(std::span<const recon::TexelStats> texels);

}  // namespace lidarscout::raster
