// evaluate_dataset: sample the survey once, then score every method on each usable patch.
#include "pipelines/evaluation.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <numeric>

#include "core/error.hpp"
#include "dataset/dataset.hpp"
#include "recon/interpolation.hpp"
#include "recon/metrics.hpp"
#include "pipelines/survey_samples.hpp"

namespace lidarscout::pipelines {

Summary summarise(const std::vector<double>& v) {
    constexpr double nan = std::numeric_limits<double>::quiet_NaN();
    if (v.empty()) return {nan, nan, nan, 0};
    const double mean = std::accumulate(v.begin(), v.end(), 0.0) / v.size();
    double var = 0;
    for (double x : v) var += (x - mean) * (x - mean);
    std::vector<double> sorted = v;
    std::sort(sorted.begin(), sorted.end());
    const std::size_t n = sorted.size();
    const double median = n % 2 ? sorted[n / 2] : 0.5 * (sorted[n / 2 - 1] + sorted[n / 2]);
    return {mean, std::sqrt(var / n), median, n};
}

namespace {

using Clock = std::chrono::steady_clock;

double ms_since(Clock::time_point t0) { return std::chrono::duration<double, std::milli>(Clock::now() - t0).count(); }

// The patch part of a window image, with NaN texels taken from `fallback` (same shape).
Image patch_of(const Image& window, const Image* fallback, int patch_texels) {
    Image out = crop_centre(window, patch_texels);
    if (!fallback) return out;
    const Image fb = crop_centre(*fallback, patch_texels);
    for (std::size_t i = 0; i < out.values.size(); ++i) {
        if (std::isnan(out.values[i])) out.values[i] = fb.values[i];
    }
    return out;
}

Image heights_in_metres(Image h, const PatchPoints& pp) {
    for (auto& v : h.values) {
        if (!std::isnan(v)) v = static_cast<float>(pp.to_metres(v));
    }
    return h;
}

struct PatchInputs {
    PatchPoints points;
    double gather_ms = 0;
};

struct TimedReconstruction {
    Reconstruction result;
    double ms = 0;
};

TimedReconstruction timed_reconstruct(const PatchPoints& points, Method method) {
    const auto t0 = Clock::now();
    Reconstruction r = reconstruct(points, method);
    return {std::move(r), ms_since(t0)};
}

// What one patch is scored against.
struct PatchTruth {
    Image height_m, rgb;
};

void add_score(MethodScores& scores, const Reconstruction& r, const Reconstruction& nearest, const PatchPoints& points,
               const PatchTruth& truth, bool has_rgb, int patch_texels, double ms) {
    const bool whole_window = r.height.size != patch_texels;  // the classic methods return the window
    const Image h = whole_window ? patch_of(r.height, &nearest.height, patch_texels) : r.height;
    scores.rmse_m.push_back(height_rmse_m(heights_in_metres(h, points), truth.height_m).value);
    if (has_rgb && !r.rgb.empty()) {
        const Image c = whole_window ? patch_of(r.rgb, &nearest.rgb, patch_texels) : r.rgb;
        scores.psnr_db.push_back(rgb_psnr_db(c, truth.rgb).value);
    }
    scores.ms.push_back(ms);
}

// Patches waiting for the networks: their inputs and what they are scored against.
struct NetworkPending {
    PatchPoints points;
    InterpolatedPatch inputs;
    Reconstruction nearest;
    PatchTruth truth;
    double ms = 0;  // gathering + interpolation
};

// The reconstructor of a network method; throws when it was not given.
const BatchReconstructor& network_of(const EvalOptions& opt, Method m) {
    const BatchReconstructor& net = m == Method::Cnn ? opt.network : opt.released;
    if (!net) {
        throw Error::in_stage("eval",
                              "the " + std::string(method_name(m)) + " method needs its network (none was loaded)");
    }
    return net;
}

class Scorer {
public:
    Scorer(const EvalOptions& opt, bool has_rgb, DatasetEvaluation& out) : opt_(opt), has_rgb_(has_rgb), out_(out) {
        for (const Method m : opt.methods) {
            if (is_network(m)) {
                networks_.emplace_back(m, &network_of(opt, m));
            } else {
                classic_.push_back(m);
            }
        }
    }

    void score(const PatchInputs& in, PatchTruth truth) {
        const int n = opt_.spec.patch_texels;
        // Nearest fills the texels other methods leave empty; it is computed once per patch.
        TimedReconstruction nearest = timed_reconstruct(in.points, Method::Nearest);
        for (const Method m : classic_) {
            const TimedReconstruction run = m == Method::Nearest ? nearest : timed_reconstruct(in.points, m);
            add_score(out_.methods[m], run.result, nearest.result, in.points, truth, has_rgb_, n,
                      run.ms + in.gather_ms);
        }
        if (networks_.empty()) return;
        const auto t0 = Clock::now();
        InterpolatedPatch inputs = interpolate_patch(in.points);
        pending_.push_back({in.points, std::move(inputs), std::move(nearest.result), std::move(truth),
                            in.gather_ms + ms_since(t0)});
        if (pending_.size() >= std::max<std::size_t>(1, opt_.batch)) flush();
    }

    void flush() {
        if (pending_.empty()) return;
        std::vector<const InterpolatedPatch*> batch;
        for (const auto& p : pending_) batch.push_back(&p.inputs);
        for (const auto& [method, network] : networks_) {
            const auto t0 = Clock::now();
            const std::vector<Reconstruction> results = (*network)(batch, has_rgb_);
            const double share = ms_since(t0) / static_cast<double>(batch.size());
            if (results.size() != batch.size()) {
                throw Error::in_stage("eval", "the network returned a wrong number of patches");
            }
            for (std::size_t i = 0; i < results.size(); ++i) {
                const NetworkPending& p = pending_[i];
                add_score(out_.methods[method], results[i], p.nearest, p.points, p.truth, has_rgb_,
                          opt_.spec.patch_texels, p.ms + share);
            }
        }
        pending_.clear();
    }

private:
    const EvalOptions& opt_;
    bool has_rgb_;
    DatasetEvaluation& out_;
    std::vector<Method> classic_;
    std::vector<std::pair<Method, const BatchReconstructor*>> networks_;
    std::vector<NetworkPending> pending_;
};

bool in_split(const RegionSplit& split, Split wanted, const PatchPoints& pp) {
    const double w = pp.spec.window_m(), r = pp.spec.radius_m();
    return split.of_window(pp.window_min_x + r, pp.window_min_y + r, pp.window_min_x, pp.window_min_y,
                           pp.window_min_x + w, pp.window_min_y + w) == wanted;
}

}  // namespace

DatasetEvaluation evaluate_dataset(const dataset::Dataset& ds, const std::string& name, const EvalOptions& opt,
                                   ThreadPool& pool, const EvalProgressFn& progress) {
    DatasetEvaluation out;
    out.name = name;
    std::vector<SampleRequest> requests;
    const std::uint64_t stride = opt.stride.value_or(auto_stride(ds, opt.spec));
    for (const Lattice& l : offset_lattices(lattice_for(ds, opt.spec), std::max(1, opt.offsets))) {
        requests.push_back({l, stride, candidate_patches(ds, l, 2 * opt.patches + 10, opt.seed)});
        out.candidates += requests.back().patches.size();
    }
    out.stride = stride;
    const SurveySamples samples = sample_survey(ds, requests, pool, progress);
    out.has_rgb = samples.has_rgb;
    out.points = samples.points;
    const RegionSplit split(opt.split_options, name);
    Scorer scorer(opt, out.has_rgb, out);
    const double texels = static_cast<double>(opt.spec.patch_texels) * opt.spec.patch_texels;
    std::size_t used = 0;
    for (std::size_t r = 0; r < requests.size(); ++r) {
        const SurveySample& s = samples.samples[r];
        for (std::size_t i = 0; i < requests[r].patches.size() && used < opt.patches; ++i) {
            const auto t0 = Clock::now();
            PatchInputs in{
                make_patch_points(*s.chunk_points, requests[r].patches[i], {opt.spec, opt.min_points, out.has_rgb}), 0};
            in.gather_ms = ms_since(t0);
            if (in.points.status != PatchStatus::Ok) {
                ++out.too_few_points;
            } else if (s.truth->covered_texels(i) < opt.min_coverage * texels) {
                ++out.low_coverage;
            } else if (opt.split && !in_split(split, *opt.split, in.points)) {
                ++out.other_split;
            } else {
                scorer.score(in, {s.truth->height_m(i), out.has_rgb ? s.truth->rgb(i) : Image{}});
                ++used;
            }
        }
    }
    scorer.flush();
    return out;
}

}  // namespace lidarscout::pipelines
