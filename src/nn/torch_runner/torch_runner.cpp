// liblidarscout_torch.so: the LibTorch side of the heightmap network (TorchScript, inference
// mode, CPU), behind the C interface of nn/runner_abi.h. Nothing here knows lidarscout's
// types; the tensor layout is nn/network_io.hpp's.
#include <ATen/Parallel.h>
#include <torch/csrc/jit/runtime/graph_executor.h>
#include <torch/script.h>

#include <cstdlib>
#include <cstring>
#include <string>

#include "nn/runner_abi.h"

namespace {

struct Model {
    torch::jit::script::Module module;
};

void set_error(char* error, size_t size, const std::string& text) {
    if (!error || size == 0) return;
    const std::string line = text.substr(0, text.find('\n'));
    std::snprintf(error, size, "%s", line.c_str());
}

// Stores every 4-d parameter (the convolution weights) channels-last. A convolution with a
// channels-last weight runs in oneDNN's NHWC layout and hands channels-last activations on to the
// next layer: the heightmap network at batch 16 takes ~0.6x the time of the default NCHW, whose
// oneDNN kernels are slow for the few-channel convolutions at 96 x 96 and in the heads
// (models/README.md, "Speed"). The values are the same; only the summation order may differ.
void use_channels_last(torch::jit::script::Module& module) {
    torch::NoGradGuard no_grad;
    for (at::Tensor p : module.parameters()) {
        if (p.dim() == 4) p.set_data(p.contiguous(at::MemoryFormat::ChannelsLast));
    }
}

// What every forward call runs under: inference mode, and the graph as exported, without the
// JIT's optimisation passes (its optimised plan ran ~0.5 ms per patch slower here; the option
// is thread-local, hence a guard per call rather than a setting at load).
struct ForwardGuards {
    c10::InferenceMode inference;
    torch::jit::GraphOptimizerEnabledGuard unoptimised{false};
};

void* open_model(const char* path, char* error, size_t error_size) {
    try {
        auto m = std::make_unique<Model>();
        m->module = torch::jit::load(path, torch::kCPU);
        m->module.eval();
        use_channels_last(m->module);
        return m.release();
    } catch (const std::exception& e) {
        set_error(error, error_size, e.what());
        return nullptr;
    }
}

// Copies a 4-d network output into malloc'd memory (freed by free_output); 0 on success.
int copy_output(const at::Tensor& result, float** output, long out_dims[4], char* error, size_t error_size) {
    const at::Tensor y = result.to(torch::kFloat32).contiguous();
    if (y.dim() != 4) {
        set_error(error, error_size, "the network's output is not a 4-d tensor");
        return 1;
    }
    for (int i = 0; i < 4; ++i) out_dims[i] = y.size(i);
    const auto count = static_cast<size_t>(y.numel());
    *output = static_cast<float*>(std::malloc(count * sizeof(float) + 1));
    if (!*output) {
        set_error(error, error_size, "out of memory for the network's output");
        return 1;
    }
    std::memcpy(*output, y.data_ptr<float>(), count * sizeof(float));
    return 0;
}

int run_model(void* model, const float* input, long n, long channels, long window, float** output, long out_dims[4],
              char* error, size_t error_size) {
    try {
        const ForwardGuards guards;
        // from_blob does not copy; the module does not write to its input.
        const auto x = torch::from_blob(const_cast<float*>(input), {n, channels, window, window}, torch::kFloat32);
        auto& module = static_cast<Model*>(model)->module;
        return copy_output(module.forward({x}).toTensor(), output, out_dims, error, error_size);
    } catch (const std::exception& e) {
        set_error(error, error_size, e.what());
        return 1;
    }
}

int run_named(void* model, const char* const* names, const float* const* inputs, int count, long n, long window,
              float** output, long out_dims[4], char* error, size_t error_size) {
    try {
        const ForwardGuards guards;
        c10::Dict<std::string, at::Tensor> batch;
        for (int i = 0; i < count; ++i) {
            const auto plane = torch::from_blob(const_cast<float*>(inputs[i]), {n, 1, window, window}, torch::kFloat32);
            batch.insert(names[i], plane);
        }
        auto& module = static_cast<Model*>(model)->module;
        return copy_output(module.forward({batch}).toTensor(), output, out_dims, error, error_size);
    } catch (const std::exception& e) {
        set_error(error, error_size, e.what());
        return 1;
    }
}

void free_output(float* output) { std::free(output); }
void close_model(void* model) { delete static_cast<Model*>(model); }
void set_threads(int threads) {
    if (threads > 0) at::set_num_threads(threads);
}

const LidarscoutRunnerApi kApi{LIDARSCOUT_RUNNER_ABI, open_model, run_model, run_named,
                               free_output, close_model, set_threads};

}  // namespace

extern "C" __attribute__((visibility("default"))) const LidarscoutRunnerApi* lidarscout_runner_api(void) {
    return &kApi;
}
