// HeightmapNetwork over the LibTorch runner plugin; the default model's lookup.
#include "nn/heightmap_network.hpp"

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string_view>

#include "core/error.hpp"
#include "core/plugin_paths.hpp"
#include "nn/network_io.hpp"
#include "nn/runner_plugin.hpp"

#ifndef LIDARSCOUT_SOURCE_DIR
#define LIDARSCOUT_SOURCE_DIR ""
#endif

namespace lidarscout::nn {
namespace fs = std::filesystem;

std::vector<std::string> model_candidates() {
    std::vector<std::string> out;
    if (const char* env = std::getenv("LIDARSCOUT_MODEL"); env && *env) out.emplace_back(env);
    if (const std::string dir = executable_dir(); !dir.empty()) {
        const fs::path d(dir);
        out.push_back((d / "models" / kDefaultModelName).string());
        out.push_back((d / ".." / "models" / kDefaultModelName).lexically_normal().string());
        out.push_back((d / ".." / "share" / "lidarscout" / "models" / kDefaultModelName).lexically_normal().string());
    }
    if (*LIDARSCOUT_SOURCE_DIR) {
        out.push_back((fs::path(LIDARSCOUT_SOURCE_DIR) / "models" / kDefaultModelName).string());
    }
    return out;
}

std::string default_model_path() {
    std::string tried;
    for (const auto& p : model_candidates()) {
        if (fs::is_regular_file(p)) return p;
        tried += (tried.empty() ? "" : ", ") + p;
    }
    throw Error("no heightmap network model found (give --model PATH or set LIDARSCOUT_MODEL); looked in: " + tried);
}

void check_model_file(const std::string& path) {
    std::error_code ec;
    if (!fs::is_regular_file(path, ec)) throw Error(path, std::nullopt, "no such heightmap network model file");
    char magic[4] = {};
    std::ifstream in(path, std::ios::binary);
    if (!in.read(magic, sizeof magic) || std::string_view(magic, 4) != std::string_view("PK\x03\x04", 4)) {
        throw Error(path, 0, "not a TorchScript model (torch.jit.save writes a zip archive)");
    }
}

struct HeightmapNetwork::Impl {
    std::string path;
    const LidarscoutRunnerApi* api = nullptr;
    void* model = nullptr;
    ~Impl() {
        if (model) api->close(model);
    }
};

HeightmapNetwork::HeightmapNetwork(std::unique_ptr<Impl> impl) : impl_(std::move(impl)) {}
HeightmapNetwork::~HeightmapNetwork() = default;
HeightmapNetwork::HeightmapNetwork(HeightmapNetwork&&) noexcept = default;
HeightmapNetwork& HeightmapNetwork::operator=(HeightmapNetwork&&) noexcept = default;

const std::string& HeightmapNetwork::path() const { return impl_->path; }

HeightmapNetwork HeightmapNetwork::load(const std::string& path, int threads) {
    auto impl = std::make_unique<Impl>();
    impl->path = path;
    impl->api = &runner_api();
    if (!fs::is_regular_file(path)) throw Error(path, std::nullopt, "cannot load the heightmap network: no such file");
    char error[512] = {};
    impl->model = impl->api->open(path.c_str(), error, sizeof error);
    if (!impl->model) throw Error(path, std::nullopt, std::string("cannot load the heightmap network: ") + error);
    impl->api->set_threads(threads);
    return HeightmapNetwork(std::move(impl));
}

namespace {

// The plugin's answer as an owned buffer of n patches; throws Error (naming `path`) on failure
// or on an output that is not [n, c, p, p].
HeightmapNetwork::RawOutput take_output(const LidarscoutRunnerApi& api, const std::string& path, int rc, float* output,
                                        const long dims[4], const char* error, std::size_t n) {
    const std::unique_ptr<float, void (*)(float*)> owned(output, api.free_output);
    if (rc != 0) throw Error(path, std::nullopt, std::string("heightmap network failed: ") + error);
    if (dims[0] != static_cast<long>(n) || dims[2] != dims[3]) {
        throw Error(path, std::nullopt, "heightmap network output has an unexpected shape");
    }
    return {std::vector<float>(output, output + dims[0] * dims[1] * dims[2] * dims[3]), dims[1], dims[2]};
}

}  // namespace

std::vector<float> HeightmapNetwork::run(std::span<const float> input, std::size_t n, int window_texels) const {
    if (input.size() != n * input_size(window_texels)) {
        throw Error(impl_->path, std::nullopt, "network input of the wrong size");
    }
    if (n == 0) return {};
    float* output = nullptr;
    long dims[4] = {};
    char error[512] = {};
    const int rc = impl_->api->run(impl_->model, input.data(), static_cast<long>(n), kInputChannels, window_texels,
                                   &output, dims, error, sizeof error);
    RawOutput out = take_output(*impl_->api, impl_->path, rc, output, dims, error, n);
    if (out.channels != kOutputChannels) {
        throw Error(impl_->path, std::nullopt, "heightmap network output has an unexpected shape");
    }
    return std::move(out.values);
}

HeightmapNetwork::RawOutput HeightmapNetwork::run_named(std::span<const char* const> names,
                                                        std::span<const float* const> planes, std::size_t n,
                                                        int window_texels) const {
    if (names.size() != planes.size()) throw Error(impl_->path, std::nullopt, "network inputs without names");
    if (n == 0) return {};
    float* output = nullptr;
    long dims[4] = {};
    char error[512] = {};
    const int rc = impl_->api->run_named(impl_->model, names.data(), planes.data(), static_cast<int>(names.size()),
                                         static_cast<long>(n), window_texels, &output, dims, error, sizeof error);
    return take_output(*impl_->api, impl_->path, rc, output, dims, error, n);
}

std::vector<recon::Reconstruction> HeightmapNetwork::infer(std::span<const recon::InterpolatedPatch* const> patches,
                                                           bool has_rgb, int patch_texels) const {
    if (patches.empty()) return {};
    const int window = patches.front()->height_nearest.size;
    const std::size_t in = input_size(window);
    std::vector<float> input(patches.size() * in);
    for (std::size_t i = 0; i < patches.size(); ++i) pack_inputs(*patches[i], std::span(input).subspan(i * in, in));
    const std::vector<float> output = run(input, patches.size(), window);
    const std::size_t out = output_size(patch_texels);
    if (output.size() != patches.size() * out) {
        throw Error(impl_->path, std::nullopt, "heightmap network output size mismatch");
    }
    std::vector<recon::Reconstruction> result;
    for (std::size_t i = 0; i < patches.size(); ++i) {
        auto r = unpack_output(std::span(output).subspan(i * out, out), patch_texels, has_rgb);
        r.method = recon::Method::Cnn;
        result.push_back(std::move(r));
    }
    return result;
}

recon::BatchReconstructor as_batch_reconstructor(std::shared_ptr<const HeightmapNetwork> network, int patch_texels) {
    return [network = std::move(network), patch_texels](std::span<const recon::InterpolatedPatch* const> patches,
                                                        bool has_rgb) {
        return network->infer(patches, has_rgb, patch_texels);
    };
}

}  // namespace lidarscout::nn
