// GroundTruth: per-texel sums of height and colour for the patches of interest.
#include "recon/ground_truth.hpp"

namespace lidarscout::recon {

GroundTruth::GroundTruth(const PatchSpec& spec, double origin_x, double origin_y, std::vector<CellKey> patches)
    : spec_(spec), origin_x_(origin_x), origin_y_(origin_y), patches_(std::move(patches)) {
    spec_.validate();
    const std::size_t texels = static_cast<std::size_t>(spec_.patch_texels) * spec_.patch_texels;
    texels_.assign(patches_.size(), std::vector<TexelStats>(texels));
    for (std::size_t i = 0; i < patches_.size(); ++i) index_.emplace(patches_[i], i);
}

void GroundTruth::add(double x, double y, double z, lidarscout::Rgb8 rgb) {
    const auto at = locate_texel(spec_, origin_x_, origin_y_, x, y);
    if (!at) return;
    const auto it = index_.find(at->cell);
    if (it == index_.end()) return;
    texels_[it->second][static_cast<std::size_t>(at->row) * spec_.patch_texels + at->col].add(z, rgb);
}

Image GroundTruth::height_m(std::size_t i) const {
    Image out(spec_.patch_texels, 1);
    const auto& acc = texels_.at(i);
    for (std::size_t t = 0; t < acc.size(); ++t) out.values[t] = acc[t].height(TexelStatistic::Mean);
    return out;
}

Image GroundTruth::rgb(std::size_t i) const {
    Image out(spec_.patch_texels, 3);
    const auto& acc = texels_.at(i);
    const std::size_t plane = acc.size();
    for (std::size_t t = 0; t < plane; ++t) {
        for (int c = 0; c < 3; ++c) out.values[c * plane + t] = acc[t].colour(c);
    }
    return out;
}

std::size_t GroundTruth::covered_texels(std::size_t i) const {
    std::size_t n = 0;
    for (const auto& a : texels_.at(i)) n += a.count > 0;
    return n;
}

}  // namespace lidarscout::recon
