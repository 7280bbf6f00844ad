// The released height network's input packing, output unpacking and loading (see
// released_model.hpp for the conventions and where they come from).
#include "nn/released_model.hpp"

#include <array>
#include <cmath>

#include "core/error.hpp"

namespace lidarscout::nn {
namespace {

constexpr double kStability = 10.0;     // numericalStabilityFactor
constexpr double kContextFactor = 1.5;  // contextRadiusFactor
// R_in / r and R_out / r, r = half our window (48 texels); the texel size cancels.
const double kInRadius = std::sqrt(0.5) * kReleasedWindow * kContextFactor / (0.5 * kReleasedWindow);
const double kOutRadius = std::sqrt(0.5) * kReleasedPatch * kContextFactor / (0.5 * kReleasedWindow);

constexpr std::array<const char*, 2> kInputNames{"patch_hm_nearest", "patch_hm_linear"};

// The two input planes of one patch, appended to `nearest` and `linear`.
void pack_released(const recon::InterpolatedPatch& p, std::vector<float>& nearest, std::vector<float>& linear) {
    if (p.status != recon::PatchStatus::Ok || p.height_nearest.size != kReleasedWindow ||
        p.height_linear.size != kReleasedWindow) {
        throw Error::in_stage("nn", "released model: the patch has no 96 x 96 interpolated heights");
    }
    const float c = p.mean_height;
    for (std::size_t i = 0; i < p.height_nearest.values.size(); ++i) {
        const float hn = std::isnan(p.height_nearest.values[i]) ? c : p.height_nearest.values[i];
        const float hl = std::isnan(p.height_linear.values[i]) ? hn : p.height_linear.values[i];
        nearest.push_back(to_released_height(hn, c));
        linear.push_back(to_released_height(hl, c));
    }
}

}  // namespace

float to_released_height(float h, float centre) { return static_cast<float>((h - centre) * kStability / kInRadius); }
float from_released_height(float out, float centre) {
    return static_cast<float>(centre + out / kStability * kOutRadius);
}

std::vector<recon::Reconstruction> infer_released(const HeightmapNetwork& model,
                                                  std::span<const recon::InterpolatedPatch* const> patches) {
    if (patches.empty()) return {};
    std::vector<float> nearest, linear;
    for (const auto* p : patches) pack_released(*p, nearest, linear);
    const std::array<const float*, 2> planes{nearest.data(), linear.data()};
    const auto out = model.run_named(kInputNames, planes, patches.size(), kReleasedWindow);
    if (out.channels < 1 || out.size != kReleasedPatch) {
        throw Error(model.path(), std::nullopt, "released model: the output is not [n, 1, 64, 64]");
    }
    const std::size_t plane = std::size_t{kReleasedPatch} * kReleasedPatch;
    std::vector<recon::Reconstruction> result;
    for (std::size_t i = 0; i < patches.size(); ++i) {
        recon::Reconstruction r;
        r.method = recon::Method::Released;
        r.status = recon::PatchStatus::Ok;
        r.height = recon::Image(kReleasedPatch, 1);
        const float* first = out.values.data() + i * out.channels * plane;
        const float centre = patches[i]->mean_height;
        for (std::size_t t = 0; t < plane; ++t) r.height.values[t] = from_released_height(first[t], centre);
        result.push_back(std::move(r));
    }
    return result;
}

std::shared_ptr<const HeightmapNetwork> load_released_model(const std::string& path, int threads) {
    auto model = std::make_shared<const HeightmapNetwork>(HeightmapNetwork::load(path, threads));
    recon::InterpolatedPatch probe;
    probe.status = recon::PatchStatus::Ok;
    probe.height_nearest = probe.height_linear = recon::Image(kReleasedWindow, 1, 0.0f);
    const recon::InterpolatedPatch* one[] = {&probe};
    try {
        infer_released(*model, one);
    } catch (const Error& e) {
        throw Error(std::string(e.what()) + " (a released file traced on CUDA runs here once converted: "
                                            "python3 -m lidarscout_train.released_cpu IN OUT)");
    }
    return model;
}

recon::BatchReconstructor released_batch_reconstructor(std::shared_ptr<const HeightmapNetwork> model) {
    return [model = std::move(model)](std::span<const recon::InterpolatedPatch* const> patches, bool) {
        return infer_released(*model, patches);
    };
}

}  // namespace lidarscout::nn
