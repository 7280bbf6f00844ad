// Evaluation of reconstruction methods against ground truth on a real survey (what
// `lidarscout eval` prints): random patches inside the data (deterministic for a seed), inputs
// from chunk points taken every K-th point, ground truth from all points, per patch the
// height RMSE (m) and colour PSNR (dB) of each method over the patch's texels that have
// ground truth, and the time each method takes.
//
// Rules worth knowing:
//   - a candidate patch is used when its window has at least min_points distinct chunk points
//     and at least min_coverage of its texels have ground truth; candidates are tried in the
//     seed's order until `patches` are used;
//   - where a method leaves a texel NaN (splatting far from every point), the nearest chunk
//     point's value is used, so every method is scored on the same texels;
//   - milliseconds per patch = gathering the window's chunk points + the method, one thread;
//     for the networks (cnn, released), + the interpolated inputs + its share of a batch
//     (`batch` patches at once, the network's own threads); a network that gives no colour
//     (released) is scored in height only;
//   - `split` scores only windows wholly inside that side of the region split
//     (region_split.hpp; the same rule and seed as `train-data`), `offsets` > 1 adds lattices
//     shifted by k/N of a patch (survey_samples.hpp) for more patches from small surveys.
#pragma once

#include <cstdint>
#include <functional>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "recon/methods.hpp"
#include "pipelines/recon_types.hpp"
#include "recon/patch_space.hpp"
#include "pipelines/region_split.hpp"

namespace lidarscout {
class ThreadPool;
}
namespace lidarscout::dataset {
struct Dataset;
}

namespace lidarscout::pipelines {

struct EvalOptions {
    std::vector<Method> methods{kAllMethods.begin(), kAllMethods.end()};
    PatchSpec spec;
    std::size_t patches = 100;
    std::uint64_t seed = 1;
    std::optional<std::uint64_t> stride;  // chunk-point stride; empty: auto_stride
    std::size_t min_points = 25;
    double min_coverage = 0.25;
    std::optional<Split> split;  // Train or Validation: only that side; empty: everywhere
    RegionSplitOptions split_options;
    int offsets = 1;
    BatchReconstructor network;   // runs Method::Cnn; required when methods has it
    BatchReconstructor released;  // runs Method::Released (nn/released_model.hpp); required when methods has it
    std::size_t batch = 16;
};

// Per-patch figures of one method.
struct MethodScores {
    std::vector<double> rmse_m;
    std::vector<double> psnr_db;  // empty when the survey has no colour
    std::vector<double> ms;
};

struct DatasetEvaluation {
    std::string name;
    std::uint64_t stride = 0;
    bool has_rgb = false;
    std::uint64_t points = 0;
    std::size_t candidates = 0, too_few_points = 0, low_coverage = 0, other_split = 0;
    std::map<Method, MethodScores> methods;
};

struct Summary {
    double mean = 0, std = 0, median = 0;
    std::size_t count = 0;
};
// Mean, population standard deviation and median; NaNs when empty.
Summary summarise(const std::vector<double>& values);

using EvalProgressFn = std::function<void(std::uint64_t points_done, std::uint64_t points_total)>;

DatasetEvaluation evaluate_dataset(const dataset::Dataset& dataset, const std::string& name, const EvalOptions& options,
                                   ThreadPool& pool, const EvalProgressFn& progress = {});

}  // namespace lidarscout::pipelines
