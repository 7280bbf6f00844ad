// The train / validation split by region, shared by `train-data` (which labels every sample)
// and `eval --split` (which scores only one side), so that both agree on which ground is
// held out.
//
// Rule: the plane (metres, the dataset's own frame) is cut into square blocks of `block_m`;
// a block is validation when a hash of (seed, dataset name, block) falls below
// `val_fraction`, else training. A window belongs to the split of its centre's block and to
// neither (Border) when it reaches into a block of the other split, so training and
// validation windows never share ground.
#pragma once

#include <cstdint>
#include <string>

namespace lidarscout::pipelines {

enum class Split { Train = 0, Validation = 1, Border = -1 };

struct RegionSplitOptions {
    double block_m = 2000.0;
    double val_fraction = 0.25;
    std::uint64_t seed = 1;
    void validate() const;  // throws lidarscout::Error on a non-positive block or a fraction outside [0, 1]
};

class RegionSplit {
public:
    RegionSplit(const RegionSplitOptions& options, const std::string& dataset_name);

    Split of_block(std::int64_t bx, std::int64_t by) const;
    // The split of the window [x0, x1] x [y0, y1] centred at (cx, cy).
    Split of_window(double cx, double cy, double x0, double y0, double x1, double y1) const;

private:
    std::int64_t block(double v) const;

    double block_m_, fraction_;
    std::uint64_t seed_;
};

// "train", "validation", "border".
const char* split_name(Split split);

}  // namespace lidarscout::pipelines
