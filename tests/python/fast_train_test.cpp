// The short-GPU-run training path (scripts/train_gpu.sh, python/lidarscout_train/window_pack.py and
// fast_train.py) end to end on the CPU: windows of two real surveys packed and unpacked, two runs
// (a leave-one-survey-out fold of the shipped recipe, relief-scaled, and the final model of the same
// with the per-window RMSE loss) trained until a deadline, bundled in float16, exported to TorchScript
// with Debian's torch and loaded by `lidarscout eval`.
#include <gtest/gtest.h>

#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <fstream>

#include "test_data.hpp"

namespace lidarscout {
namespace {

namespace fs = std::filesystem;

int run(const std::string& command, std::string& out) { return test::run_command(command + " 2>&1", out); }

TEST(PythonFastTrain, TinyRunEndToEndOnTheCpu) {
    const fs::path dir = fs::temp_directory_path() / ("lidarscout_fast_train_" + std::to_string(::getpid()));
    fs::remove_all(dir);
    fs::create_directories(dir / "data");
    const std::string cli = LIDARSCOUT_CLI;
    const fs::path repo = LIDARSCOUT_SOURCE_DIR;
    std::string out;
    // Two sources, named as `train_gpu.sh data` names its files (SOURCE.cpN.bin, SOURCE.fine.bin).
    ASSERT_EQ(run(cli + " train-data " + (test::surveys_dir() / "ky-woodford-county").string() + " -o " +
                      (dir / "data" / "flat.cp369.bin").string() +
                      " --texel 10 --patches 3 --offsets 2 --val-fraction 0",
                  out),
              0)
        << out;
    ASSERT_EQ(run(cli + " train-data " + (test::surveys_dir() / "lasr-bcts-strips").string() + " -o " +
                      (dir / "data" / "strips.fine.bin").string() + " --texel 2.5,5 --patches 3 --val-fraction 0",
                  out),
              0)
        << out;
    ASSERT_EQ(run("cd " + (repo / "python").string() + " && /usr/bin/python3 -m lidarscout_train.window_pack pack " +
                      (dir / "data" / "flat.cp369.bin").string() + " " + (dir / "data" / "strips.fine.bin").string() +
                      " --out " + (dir / "windows.xz").string() + " --per-group 4 --surveys flat,strips",
                  out),
              0)
        << out;
    EXPECT_NE(out.find("2 sources (2 folds)"), std::string::npos) << out;

    ASSERT_EQ(run((repo / "scripts" / "train_gpu.sh").string() + " run --tree " + dir.string() +
                      " --device cpu --tiny --budget 12 --out " + (dir / "back").string(),
                  out),
              0)
        << out;
    EXPECT_TRUE(fs::is_regular_file(dir / "back" / "models-0.pt")) << out;
    ASSERT_EQ(run((repo / "scripts" / "train_gpu.sh").string() + " export --from " + (dir / "back").string() +
                      " --work " + (dir / "work").string(),
                  out),
              0)
        << out;
    const fs::path fold = dir / "work" / "runs" / "shipped-scaled-fold-flat";
    ASSERT_TRUE(fs::is_regular_file(fold / "model.pt")) << out;
    const fs::path final_run = dir / "work" / "runs" / "shipped-scaled-rmse-final";
    EXPECT_TRUE(fs::is_regular_file(final_run / "model.pt")) << out;
    std::ifstream hf(final_run / "history.json");
    EXPECT_EQ(nlohmann::json::parse(hf).at("config").at("loss").get<std::string>(), "rmse");

    std::ifstream h(fold / "history.json");
    const auto history = nlohmann::json::parse(h);
    EXPECT_GT(history.at("steps").get<int>(), 0);
    EXPECT_EQ(history.at("config").at("held_out").get<std::string>(), "flat");
    EXPECT_EQ(history.at("config").at("weights").get<std::string>(), "group");
    EXPECT_EQ(history.at("config").at("loss").get<std::string>(), "mse");
    EXPECT_TRUE(history.at("config").at("relief_scale").get<bool>());
    const auto& figures = history.at("held_out");
    ASSERT_EQ(figures.size(), 1u);  // the flat survey's 10 m windows at one density
    EXPECT_EQ(figures[0].at("texel_m").get<double>(), 10.0);
    EXPECT_EQ(figures[0].at("density").get<int>(), 369);
    const double ratio = figures[0].at("ratio").get<double>();
    EXPECT_TRUE(std::isfinite(ratio) && ratio > 0) << ratio;
    const auto& epochs = history.at("epochs");
    ASSERT_FALSE(epochs.empty());
    for (const auto& e : epochs) {  // the clock's schedule never passes the peak (its shape: the self-test)
        EXPECT_GT(e.at("lr_end").get<double>(), 0.0);
        EXPECT_LE(e.at("lr_end").get<double>(), 4e-4 * (1 + 1e-9));
    }

    // The exported model runs in the C++ evaluation.
    ASSERT_EQ(run(cli + " eval " + (test::surveys_dir() / "ky-woodford-county").string() +
                      " --methods linear,cnn --model " + (fold / "model.pt").string() +
                      " --texel 10 --patches 2 --offsets 1 --json",
                  out),
              0)
        << out;
    EXPECT_NE(out.find("\"cnn\""), std::string::npos) << out;
    fs::remove_all(dir);
}

}  // namespace
}  // namespace lidarscout
