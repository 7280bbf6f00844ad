// Inputs and ground truth for evaluation and training, from real surveys in one streaming
// pass: every tile is decoded once, in file order; every K-th point (the first of each
// K-point run, exactly what a LAZ with K-point chunks would store raw) becomes a chunk point,
// and every point feeds the ground truth of the patches of interest. Several patch specs
// (texel sizes) are served by the same pass, each with its own stride and lattice.
//
// The stride rule (--stride auto): a real survey of 20 points/m^2 in 50,000-point chunks has
// one chunk point per 2,500 m^2, i.e. about 369 in a 960 m window. For a survey of density D
// and a window of side W metres, K = round(D * W^2 / (20 * 960^2 / 50,000)), at least 1, so
// the window holds about as many chunk points as the real case. D is the median over tiles of
// points / (header bounding-box area).
#pragma once

#include <cstdint>
#include <functional>
#include <memory>
#include <vector>

#include "core/patch_grid.hpp"
#include "recon/ground_truth.hpp"
#include "pipelines/recon_types.hpp"
#include "recon/patch_space.hpp"

namespace lidarscout {
class ThreadPool;
}
namespace lidarscout::dataset {
struct Dataset;
}

namespace lidarscout::pipelines {

inline constexpr double kReferenceDensity = 20.0;          // points / m^2 of a typical survey
inline constexpr double kReferenceChunkPoints = 50'000.0;  // points per LAZ chunk
inline constexpr double kReferenceWindowM = 960.0;         // the paper's window

// Median over tiles of point_count / bounding-box area (points per m^2); 0 when unknown.
double point_density(const dataset::Dataset& dataset);
// The stride of the rule above for `spec`'s window.
std::uint64_t auto_stride(const dataset::Dataset& dataset, const PatchSpec& spec);

// The lattice of a spec over a dataset: its origin (dataset min corner rounded down to a
// multiple of the patch size).
struct Lattice {
    PatchSpec spec;
    double origin_x = 0, origin_y = 0;
};
Lattice lattice_for(const dataset::Dataset& dataset, const PatchSpec& spec);
// `count` lattices: `base` shifted diagonally by k/count of a patch, k = 0..count-1.
std::vector<Lattice> offset_lattices(const Lattice& base, int count);

// Up to `count` patches (cells of the lattice) that hold some of the dataset's real chunk
// points (so they are inside the data), in a random order that depends only on `seed`.
std::vector<lidarscout::CellKey> candidate_patches(const dataset::Dataset& dataset, const Lattice& lattice,
                                               std::size_t count, std::uint64_t seed);

struct SampleRequest {
    Lattice lattice;
    std::uint64_t stride = 50'000;
    std::vector<lidarscout::CellKey> patches;  // where ground truth is wanted
};

struct SurveySample {
    Lattice lattice;
    std::uint64_t stride = 0;
    std::unique_ptr<lidarscout::PatchGrid> chunk_points;  // cells = the lattice's patches
    std::unique_ptr<GroundTruth> truth;
};

struct SurveySamples {
    std::vector<SurveySample> samples;  // one per request, same order
    bool has_rgb = false;               // at least half of the points have a colour other than black
    std::uint64_t points = 0;           // points streamed
};

// Streams every tile of `dataset` once. `progress(points_done, points_total)` is called
// between batches. Throws lidarscout::Error when a tile cannot be decoded.
SurveySamples sample_survey(const dataset::Dataset& dataset, const std::vector<SampleRequest>& requests,
                            ThreadPool& pool, const std::function<void(std::uint64_t, std::uint64_t)>& progress = {});

}  // namespace lidarscout::pipelines
