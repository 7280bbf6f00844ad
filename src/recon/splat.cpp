// Splatting baseline: per-texel means, then a separable normalised Gaussian convolution (see
// splat.hpp).
#include "recon/splat.hpp"

#include <algorithm>
#include <cmath>
#include <vector>

#include "core/error.hpp"

namespace lidarscout::recon {
namespace {

int texel_of(double grid, int size) {
    return std::clamp(static_cast<int>(std::floor(grid / static_cast<double>(kGridUnitsPerTexel))), 0, size - 1);
}

std::vector<double> gaussian_kernel(const SplatOptions& options) {
    std::vector<double> k(2 * options.radius_texels + 1);
    for (int d = -options.radius_texels; d <= options.radius_texels; ++d) {
        k[d + options.radius_texels] = std::exp(-0.5 * d * d / (options.sigma_texels * options.sigma_texels));
    }
    return k;
}

// Separable convolution of a size x size plane with zero outside: rows, then columns.
std::vector<double> convolve(const std::vector<double>& plane, int size, const std::vector<double>& kernel) {
    const int radius = static_cast<int>(kernel.size() / 2);
    std::vector<double> rows(plane.size(), 0.0), out(plane.size(), 0.0);
    for (int r = 0; r < size; ++r) {
        for (int c = 0; c < size; ++c) {
            double sum = 0.0;
            for (int d = std::max(-radius, -c); d <= std::min(radius, size - 1 - c); ++d) {
                sum += kernel[d + radius] * plane[r * size + c + d];
            }
            rows[r * size + c] = sum;
        }
    }
    for (int r = 0; r < size; ++r) {
        for (int c = 0; c < size; ++c) {
            double sum = 0.0;
            for (int d = std::max(-radius, -r); d <= std::min(radius, size - 1 - r); ++d) {
                sum += kernel[d + radius] * rows[(r + d) * size + c];
            }
            out[r * size + c] = sum;
        }
    }
    return out;
}

}  // namespace

SplatResult splat(std::span<const GridXY> points, const PointValues& values, int size, const SplatOptions& options) {
    if (values.count != points.size()) throw Error::in_stage("recon", "splat needs one value per point");
    if (!(options.sigma_texels > 0.0) || options.radius_texels < 0) throw Error::in_stage("recon", "bad splat kernel");
    const std::size_t texels = static_cast<std::size_t>(size) * size;
    std::vector<int> count(texels, 0);
    std::vector<std::size_t> texel_of_point(points.size());
    for (std::size_t i = 0; i < points.size(); ++i) {
        texel_of_point[i] = static_cast<std::size_t>(texel_of(points[i].y, size)) * size + texel_of(points[i].x, size);
        ++count[texel_of_point[i]];
    }
    const auto kernel = gaussian_kernel(options);
    std::vector<double> mask(texels, 0.0);
    for (std::size_t t = 0; t < texels; ++t) mask[t] = count[t] > 0 ? 1.0 : 0.0;
    const std::vector<double> weight = convolve(mask, size, kernel);

    SplatResult out{Image(size, values.channels), Image(size, 1)};
    for (std::size_t t = 0; t < texels; ++t) out.weights.values[t] = static_cast<float>(weight[t]);
    for (int c = 0; c < values.channels; ++c) {
        std::vector<double> mean(texels, 0.0);
        for (std::size_t i = 0; i < points.size(); ++i) mean[texel_of_point[i]] += values.value(c, i);
        for (std::size_t t = 0; t < texels; ++t) {
            if (count[t] > 0) mean[t] /= count[t];
        }
        const std::vector<double> sum = convolve(mean, size, kernel);
        auto plane = out.values.plane(c);
        for (std::size_t t = 0; t < texels; ++t) {
            plane[t] = weight[t] > 0.0 ? static_cast<float>(sum[t] / weight[t]) : kNoValue;
        }
    }
    return out;
}

}  // namespace lidarscout::recon
