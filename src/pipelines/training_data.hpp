// Training samples for the heightmap network (`lidarscout train-data`), written as one file
// that numpy reads without any other package:
//
//   bytes 0..47   preamble: "LSTRAIN1" (8 bytes), then five little-endian uint64:
//                 records_offset, record_size, count, meta_offset, meta_length
//   records       `count` fixed-size records from records_offset, one per sample; the fields
//                 of a record, in order (numpy: np.memmap(path, dtype=np.dtype(fields),
//                 offset=records_offset, shape=(count,))):
//                   height_in  float16 [2, 96, 96]  nearest, linear; normalised heights
//                   rgb_in     uint8   [6, 96, 96]  nearest r,g,b, linear r,g,b (0..255; 0 without colour)
//                   height_gt  float16 [64, 64]     mean height per texel, normalised; NaN = none
//                   rgb_gt     uint8   [3, 64, 64]  mean colour per texel (0 where none)
//                   mask       uint8   [64, 64]     1 where the texel has ground truth
//                   has_rgb    uint8                1 when the survey has colour
//                   split      uint8                0 train, 1 validation
//   meta          UTF-8 JSON at meta_offset: {"format": "lidarscout-train", "version": 1,
//                 "fields": [[name, numpy dtype, shape], ...], "samples": [{dataset, tile,
//                 centre_x, centre_y, texel_m, centre_z, radius_m, stride, split}, ...],
//                 "normalisation": text}
//
// Normalisation is patch_space.hpp's: h' = (z - centre_z) / radius_m, radius = half the window.
// (Image sizes above are for the default 64-texel patch with 16 texels of padding.)
//
// Region split: pipelines/region_split.hpp (shared with `eval --split`); a patch whose padded
// window reaches into a block of the other split is dropped, so training and validation
// windows never share ground.
//
// Offsets: with offsets = N > 1, each texel size is sampled on N lattices shifted
// diagonally by k/N of a patch (k = 0..N-1): more (overlapping) samples from small surveys.
#pragma once

#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <vector>

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

inline constexpr char kTrainingMagic[9] = "LSTRAIN1";

struct TrainingDataOptions {
    std::vector<double> texels_m{10.0};
    std::size_t patches = 100;  // per dataset and texel size
    std::uint64_t seed = 1;
    std::optional<std::uint64_t> stride;  // empty: auto_stride per texel size
    RegionSplitOptions split;
    int offsets = 1;  // lattices per texel size
    std::size_t min_points = 25;
    double min_coverage = 0.25;
};

struct NamedDataset {
    std::string name;
    const dataset::Dataset* dataset = nullptr;
};

struct TrainingDataSummary {
    std::size_t samples = 0, train = 0, validation = 0, dropped_at_split_border = 0;
    std::uint64_t bytes = 0;
};

// Streams each dataset once and writes `out_path` (atomically). progress(dataset index,
// points done, points total).
TrainingDataSummary write_training_data(
    const std::vector<NamedDataset>& datasets, const TrainingDataOptions& options, const std::string& out_path,
    ThreadPool& pool, const std::function<void(std::size_t, std::uint64_t, std::uint64_t)>& progress = {});

}  // namespace lidarscout::pipelines
