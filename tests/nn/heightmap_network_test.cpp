// HeightmapNetwork: a TorchScript model exported by the Python training code gives, through
// LibTorch, the same output as the eager PyTorch model, for a batch larger than the one it was
// traced with, also from several threads at once; bad files are one clear error.
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <thread>

#include "core/error.hpp"
#include "nn/heightmap_network.hpp"
#include "nn/network_io.hpp"
#include "test_data.hpp"

namespace lidarscout::nn {
namespace {

namespace fs = std::filesystem;

std::vector<float> read_floats(const fs::path& p) {
    std::ifstream in(p, std::ios::binary);
    std::vector<float> v(fs::file_size(p) / sizeof(float));
    in.read(reinterpret_cast<char*>(v.data()), static_cast<std::streamsize>(v.size() * sizeof(float)));
    return v;
}

// Exported once per process by python/lidarscout_train/reference_io.py.
const fs::path& reference_dir() {
    static const fs::path dir = [] {
        const fs::path d = fs::temp_directory_path() / ("lidarscout_nn_ref_" + std::to_string(::getpid()));
        std::string out;
        const int rc =
            test::run_command("cd " + (fs::path(LIDARSCOUT_SOURCE_DIR) / "python").string() +
                                  " && /usr/bin/python3 -m lidarscout_train.reference_io " + d.string() + " 2>&1",
                              out);
        EXPECT_EQ(rc, 0) << out;
        return d;
    }();
    return dir;
}

TEST(HeightmapNetwork, MatchesPyTorchForABatchOfThree) {
    const auto net = HeightmapNetwork::load((reference_dir() / "model.pt").string());
    const auto input = read_floats(reference_dir() / "input.bin");
    const auto expected = read_floats(reference_dir() / "output.bin");
    ASSERT_EQ(input.size(), 3 * input_size(96));
    ASSERT_EQ(expected.size(), 3 * output_size(64));
    const auto got = net.run(input, 3, 96);
    ASSERT_EQ(got.size(), expected.size());
    for (std::size_t i = 0; i < got.size(); ++i) ASSERT_NEAR(got[i], expected[i], 1e-4) << i;
}

TEST(HeightmapNetwork, ThreadSafe) {
    const auto net = HeightmapNetwork::load((reference_dir() / "model.pt").string());
    const auto input = read_floats(reference_dir() / "input.bin");
    const auto expected = read_floats(reference_dir() / "output.bin");
    std::vector<std::vector<float>> results(4);
    std::vector<std::thread> threads;
    for (int t = 0; t < 4; ++t) threads.emplace_back([&, t] { results[t] = net.run(input, 3, 96); });
    for (auto& t : threads) t.join();
    for (const auto& r : results) {
        ASSERT_EQ(r.size(), expected.size());
        for (std::size_t i = 0; i < r.size(); i += 97) EXPECT_NEAR(r[i], expected[i], 1e-4);
    }
}

TEST(HeightmapNetwork, BadFilesAreOneLineErrors) {
    const fs::path bad = fs::temp_directory_path() / ("lidarscout_bad_model_" + std::to_string(::getpid()) + ".pt");
    std::ofstream(bad) << "not a model";
    try {
        HeightmapNetwork::load(bad.string());
        FAIL() << "loaded garbage";
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find(bad.string()), std::string::npos);
        EXPECT_EQ(std::string(e.what()).find('\n'), std::string::npos);
    }
    EXPECT_THROW(HeightmapNetwork::load("/nonexistent/model.pt"), Error);
    fs::remove(bad);
}

}  // namespace
}  // namespace lidarscout::nn
