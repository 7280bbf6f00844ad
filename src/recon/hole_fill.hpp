// Pull-push hole filling of a square raster: the NaN texels a caller wants filled take values
// interpolated from the defined ones through a pyramid of averages. Used by the viewer's bare
// earth (holes under roofs and canopy) and by the ground filter (empty cells, removed objects).
#pragma once

#include <vector>

namespace lidarscout::recon {

// Fills the NaN texels of `heights` (size x size) that `wanted` marks by pull-push interpolation
// from the defined ones: each coarser level averages the defined texels below it, then every
// wanted hole takes the value of the finest level that defines it, blended bilinearly. Leaves
// every other texel as it is; no-op (false) when no texel is defined.
bool hole_fill(std::vector<float>& heights, int size, const std::vector<bool>& wanted);

// The raster (size x size, rows from the south) at (u, v) cells from its south-west corner,
// bilinear between cell centres and clamped at the edges.
float sample_bilinear(const std::vector<float>& raster, int size, double u, double v);

}  // namespace lidarscout::recon
