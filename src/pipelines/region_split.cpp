// RegionSplit: hashed square blocks (see region_split.hpp).
#include "pipelines/region_split.hpp"

#include <cmath>

#include "core/error.hpp"
#include "core/random.hpp"

namespace lidarscout::pipelines {
namespace {

std::uint64_t fnv1a(const std::string& s) {
    std::uint64_t h = 0xcbf29ce484222325ull;
    for (unsigned char c : s) h = (h ^ c) * 0x100000001b3ull;
    return h;
}

}  // namespace

void RegionSplitOptions::validate() const {
    if (!(block_m > 0) || !(val_fraction >= 0 && val_fraction <= 1)) {
        throw Error("region split: the block must be positive and the validation fraction in [0, 1]");
    }
}

RegionSplit::RegionSplit(const RegionSplitOptions& o, const std::string& dataset_name)
    : block_m_(o.block_m), fraction_(o.val_fraction), seed_(hash_of(o.seed, fnv1a(dataset_name))) {
    o.validate();
}

std::int64_t RegionSplit::block(double v) const { return static_cast<std::int64_t>(std::floor(v / block_m_)); }

Split RegionSplit::of_block(std::int64_t bx, std::int64_t by) const {
    return unit_of(hash_of(seed_, bx, by)) < fraction_ ? Split::Validation : Split::Train;
}

Split RegionSplit::of_window(double cx, double cy, double x0, double y0, double x1, double y1) const {
    const Split split = of_block(block(cx), block(cy));
    for (std::int64_t bx = block(x0); bx <= block(x1); ++bx) {
        for (std::int64_t by = block(y0); by <= block(y1); ++by) {
            if (of_block(bx, by) != split) return Split::Border;
        }
    }
    return split;
}

const char* split_name(Split split) {
    switch (split) {
        case Split::Train: return "train";
        case Split::Validation: return "validation";
        case Split::Border: return "border";
    }
    return "?";
}

}  // namespace lidarscout::pipelines
