// Ground truth for a set of patches: the mean height and mean colour of all full-resolution
// points that fall into each texel of each patch (NaN where no point falls). Points are fed
// one at a time as tiles are streamed, so no tile (let alone the dataset) is held in memory.
// Patches are cells of a lattice of patch_m squares anchored at (origin_x, origin_y), the same
// lattice as the PatchGrid the chunk points go into. Points are gridded by texel_stats.hpp.
#pragma once

#include <cstdint>
#include <unordered_map>
#include <vector>

#include "core/patch_grid.hpp"
#include "recon/patch_space.hpp"
#include "recon/texel_stats.hpp"

namespace lidarscout::recon {

class GroundTruth {
public:
    GroundTruth(const PatchSpec& spec, double origin_x, double origin_y, std::vector<lidarscout::CellKey> patches);

    // Adds one point (metres, colour in 8 bits) to the texel it falls in, when it falls in one
    // of the patches.
    void add(double x, double y, double z, lidarscout::Rgb8 rgb);

    const std::vector<lidarscout::CellKey>& patches() const { return patches_; }
    // Patch `i` as images of patch_texels x patch_texels (rows along y, as patch_space.hpp):
    // mean height in metres (1 channel) and mean colour in [0, 1] (3 channels); NaN where no
    // point fell.
    Image height_m(std::size_t i) const;
    Image rgb(std::size_t i) const;
    // Texels of patch `i` that received at least one point.
    std::size_t covered_texels(std::size_t i) const;

private:
    PatchSpec spec_;
    double origin_x_, origin_y_;
    std::vector<lidarscout::CellKey> patches_;
    std::unordered_map<lidarscout::CellKey, std::size_t, lidarscout::CellKeyHash> index_;
    std::vector<std::vector<TexelStats>> texels_;  // per patch, row-major
};

}  // namespace lidarscout::recon
