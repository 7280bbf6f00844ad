// Baseline "splat" (high-quality splatting as the paper's HQSplat, Botsch et al. 2005, with a
// fixed Gaussian kernel): each texel first takes the mean of the chunk points that fall into
// it (a point on the window's max edge counts for the last texel), then every texel gets the
// normalised Gaussian convolution of those means,
//     out(t) = sum_s w(t - s) mean(s) / sum_s w(t - s)   over texels s holding points,
//     w(dx, dy) = exp(-(dx^2 + dy^2) / (2 sigma^2)) for |dx|, |dy| <= radius (texels),
// with sigma = 2.25 texels and radius = 16 texels (the reference's values). A texel with no
// point within the radius has no weight and stays NaN (no fallback).
#pragma once

#include <span>

#include "recon/patch_space.hpp"

namespace lidarscout::recon {

struct SplatOptions {
    double sigma_texels = 2.25;
    int radius_texels = 16;
};

struct SplatResult {
    Image values;   // values.channels channels, NaN where weight is 0
    Image weights;  // 1 channel: sum of the kernel weights of the texels holding points
};

// `points` and `values` in the same order; `size` texels per side.
SplatResult splat(std::span<const GridXY> points, const PointValues& values, int size,
                  const SplatOptions& options = {});

}  // namespace lidarscout::recon
