// Per-texel statistics of full-resolution points on a lattice of patches: where a point falls
// (the patch and the texel inside it) and what a texel accumulates (count, height sum, min,
// max, colour sums). Shared by the ground truth of `eval` (ground_truth.hpp) and the DEMs made
// from every point (raster/full_dem.hpp), so both grid points the same way, to the bit.
#pragma once

#include <cstdint>
#include <limits>
#include <optional>

#include "core/patch_grid.hpp"
#include "recon/patch_space.hpp"

namespace lidarscout::recon {

// A texel of a lattice of patch_m squares anchored at the lattice origin: the patch (cell)
// and the column (along x) and row (along y, south to north) inside it.
struct TexelLocation {
    lidarscout::CellKey cell;
    int col = 0, row = 0;
};

// Where (x, y) (metres) falls; empty for NaN or points absurdly far from the origin.
std::optional<TexelLocation> locate_texel(const PatchSpec& spec, double origin_x, double origin_y, double x, double y);

enum class TexelStatistic { Mean, Min, Max };

struct TexelStats {
    double z_sum = 0;
    float z_min = std::numeric_limits<float>::infinity();
    float z_max = -std::numeric_limits<float>::infinity();
    std::uint32_t r = 0, g = 0, b = 0;
    std::uint32_t count = 0;

    void add(double z, lidarscout::Rgb8 rgb);
    // The statistic's height in metres (the mean in double, rounded once); NaN when empty.
    float height(TexelStatistic statistic) const;
    // Mean colour channel c (0..2) in [0, 1]; NaN when empty.
    float colour(int c) const;
};

}  // namespace lidarscout::recon
