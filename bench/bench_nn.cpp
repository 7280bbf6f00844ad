// Benchmark: the heightmap network's inference on the CPU, ms per patch at batch sizes 1, 4
// and 16 (wall time, median of --runs runs of --repeat batches each, after a warm-up), with a
// given number of LibTorch threads (default 2). Inputs are a tilted plane with noise: the
// time does not depend on the values.
// Usage: bench_nn [--model FILE] [--threads N] [--runs N] [--repeat N] [--batches 1,4,16]
#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <cstdlib>
#include <random>
#include <string>
#include <vector>

#include "bench_main.hpp"
#include "core/error.hpp"
#include "nn/heightmap_network.hpp"
#include "nn/network_io.hpp"

using namespace lidarscout;

namespace {

struct Options {
    std::string model;
    int threads = 2, runs = 5, repeat = 8;
    std::vector<int> batches{1, 4, 16};
};

Options parse(int argc, char** argv) {
    Options o;
    for (int i = 1; i < argc; ++i) {
        const std::string a = argv[i];
        if (i + 1 >= argc) throw Error("bench_nn: " + a + " needs a value");
        const std::string v = argv[++i];
        if (a == "--model") o.model = v;
        else if (a == "--threads") o.threads = std::stoi(v);
        else if (a == "--runs") o.runs = std::stoi(v);
        else if (a == "--repeat") o.repeat = std::stoi(v);
        else if (a == "--batches") {
            o.batches.clear();
            for (std::size_t s = 0; s <= v.size();) {
                const std::size_t e = std::min(v.find(',', s), v.size());
                o.batches.push_back(std::stoi(v.substr(s, e - s)));
                s = e + 1;
            }
        } else {
            throw Error("bench_nn: unknown option " + a);
        }
    }
    return o;
}

std::vector<float> plane_inputs(int n, int window) {
    std::mt19937 rng(1);
    std::normal_distribution<float> noise(0.0f, 0.01f);
    const std::size_t plane = std::size_t(window) * window;
    std::vector<float> in(n * nn::input_size(window));
    for (int b = 0; b < n; ++b) {
        float* p = in.data() + b * nn::input_size(window);
        for (int r = 0; r < window; ++r) {
            for (int c = 0; c < window; ++c) {
                const float h = 0.002f * (r - window / 2) + 0.001f * (c - window / 2);
                p[r * window + c] = h + noise(rng);
                p[plane + r * window + c] = h;
                for (int ch = 2; ch < 8; ++ch) p[ch * plane + r * window + c] = 0.4f + noise(rng);
            }
        }
    }
    return in;
}

double ms_per_patch(const nn::HeightmapNetwork& net, int batch, const Options& o) {
    constexpr int kWindow = 96;
    const auto input = plane_inputs(batch, kWindow);
    for (int k = 0; k < 3; ++k) net.run(input, batch, kWindow);  // warm-up (TorchScript profiles its first calls)
    std::vector<double> runs;
    for (int r = 0; r < o.runs; ++r) {
        const auto t0 = std::chrono::steady_clock::now();
        for (int k = 0; k < o.repeat; ++k) net.run(input, batch, kWindow);
        const double ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
        runs.push_back(ms / (o.repeat * batch));
    }
    std::sort(runs.begin(), runs.end());
    return runs[runs.size() / 2];
}

}  // namespace

constexpr const char* kUsage =
    "[--model FILE] [--threads N] [--runs N] [--repeat N] [--batches 1,4,16]";

int main(int argc, char** argv) {
    return lidarscout::bench::bench_main("bench_nn", kUsage, argc, argv, [](int argc, char** argv) {
        const Options o = parse(argc, argv);
        const std::string path = o.model.empty() ? nn::default_model_path() : o.model;
        const auto net = nn::HeightmapNetwork::load(path, o.threads);
        fmt::print("model {}\nthreads {}, median of {} runs of {} batches\n", path, o.threads, o.runs, o.repeat);
        fmt::print("{:>6} {:>12}\n", "batch", "ms/patch");
        for (int b : o.batches) fmt::print("{:>6} {:>12.2f}\n", b, ms_per_patch(net, b, o));
        return 0;
    });
}
