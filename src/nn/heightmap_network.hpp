// Running the heightmap network (a TorchScript file exported by python/lidarscout_train) on
// the CPU: batches of patches in, one reconstruction per patch out. The tensor interface is
// nn/network_io.hpp's. LibTorch lives in a plugin opened on the first load
// (nn/runner_plugin.hpp), so this header and its users never link it. Thread-safe: several
// threads may call infer()/run() at once (inference only).
//
// The default model: models/heightmap_cnn.pt, found by default_model_path().
#pragma once

#include <memory>
#include <span>
#include <string>
#include <vector>

#include "recon/interpolation.hpp"
#include "recon/methods.hpp"

namespace lidarscout::nn {

inline constexpr char kDefaultModelName[] = "heightmap_cnn.pt";

// Where the shipped model is looked for, in order: $LIDARSCOUT_MODEL, models/ next to the
// program and one folder up (the build folder sits in the source tree), share/lidarscout/models
// of an installation, and the source tree this program was built from.
std::vector<std::string> model_candidates();
// The first candidate that exists; throws lidarscout::Error listing them all when none does.
std::string default_model_path();
// Throws lidarscout::Error naming `path` when it is not a readable TorchScript file (a zip archive,
// as torch.jit.save writes): a cheap check before a window opens, without loading LibTorch.
void check_model_file(const std::string& path);

class HeightmapNetwork {
public:
    // Loads a TorchScript model; throws lidarscout::Error (naming the file) when it cannot.
    // threads > 0 sets the runtime's intra-op threads (process-wide).
    static HeightmapNetwork load(const std::string& path, int threads = 0);
    ~HeightmapNetwork();
    HeightmapNetwork(HeightmapNetwork&&) noexcept;
    HeightmapNetwork& operator=(HeightmapNetwork&&) noexcept;

    const std::string& path() const;

    // One reconstruction (64 x 64 for the default spec) per patch, in order. `has_rgb` tells
    // whether the survey has colour (else the colour output is NaN).
    std::vector<recon::Reconstruction> infer(std::span<const recon::InterpolatedPatch* const> patches, bool has_rgb,
                                             int patch_texels = 64) const;

    // Runs raw input planes [n, 8, w, w] and returns the raw output [n, 4, p, p] (for tests and
    // benchmarks).
    std::vector<float> run(std::span<const float> input, std::size_t n, int window_texels) const;

    // Runs a model whose forward takes one dict of named planes (the paper's released networks,
    // nn/released_model.hpp): planes[i], float32 [n, 1, w, w], under names[i]. Returns the raw
    // output [n, c, p, p] (c = channels, p = size).
    struct RawOutput {
        std::vector<float> values;
        long channels = 0, size = 0;
    };
    RawOutput run_named(std::span<const char* const> names, std::span<const float* const> planes, std::size_t n,
                        int window_texels) const;

private:
    struct Impl;
    explicit HeightmapNetwork(std::unique_ptr<Impl> impl);
    std::unique_ptr<Impl> impl_;
};

// The network as a recon::BatchReconstructor (for evaluation); shares ownership.
recon::BatchReconstructor as_batch_reconstructor(std::shared_ptr<const HeightmapNetwork> network,
                                                 int patch_texels = 64);

}  // namespace lidarscout::nn
