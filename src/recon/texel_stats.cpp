// locate_texel and TexelStats: the gridding arithmetic of the ground truth and the full DEMs.
#include "recon/texel_stats.hpp"

#include <algorithm>
#include <cmath>

namespace lidarscout::recon {

std::optional<TexelLocation> locate_texel(const PatchSpec& spec, double origin_x, double origin_y, double x, double y) {
    const double patch_m = spec.patch_m();
    const double fx = std::floor((x - origin_x) / patch_m);
    const double fy = std::floor((y - origin_y) / patch_m);
    if (!(std::abs(fx) < 2e9 && std::abs(fy) < 2e9)) return std::nullopt;  // NaN or far outside any patch
    const int n = spec.patch_texels;
    TexelLocation at;
    at.cell = {static_cast<std::int32_t>(fx), static_cast<std::int32_t>(fy)};
    at.col = std::clamp(static_cast<int>((x - origin_x - fx * patch_m) / spec.texel_m), 0, n - 1);
    at.row = std::clamp(static_cast<int>((y - origin_y - fy * patch_m) / spec.texel_m), 0, n - 1);
    return at;
}

void TexelStats::add(double z, lidarscout::Rgb8 rgb) {
    z_sum += z;
    const auto zf = static_cast<float>(z);
    z_min = std::min(z_min, zf);
    z_max = std::max(z_max, zf);
    r += rgb.r;
    g += rgb.g;
    b += rgb.b;
    ++count;
}

float TexelStats::height(TexelStatistic statistic) const {
    if (count == 0) return kNoValue;
    switch (statistic) {
        case TexelStatistic::Min: return z_min;
        case TexelStatistic::Max: return z_max;
        case TexelStatistic::Mean: break;
    }
    return static_cast<float>(z_sum / count);
}

float TexelStats::colour(int c) const {
    if (count == 0) return kNoValue;
    const std::uint32_t sum = c == 0 ? r : c == 1 ? g : b;
    return static_cast<float>(sum * (1.0 / (255.0 * count)));
}

}  // namespace lidarscout::recon
