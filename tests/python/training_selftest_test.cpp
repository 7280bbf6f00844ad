// The Python training package (python/lidarscout_train) in the suite: its self-test builds both
// decoder variants, checks shapes and parameter counts, runs one training step, exports to
// TorchScript and reloads it (with /usr/bin/python3 and Debian's python3-torch); and one
// training step of train.py on a tiny file that `lidarscout train-data` generates, then
// fine-tuning from its state dict and from its TorchScript model (on a capped subset).
#include <gtest/gtest.h>

#include <unistd.h>

#include <filesystem>
#include <fstream>

#include <cmath>

#include "test_data.hpp"

namespace lidarscout {
namespace {

TEST(PythonTraining, SelfTestPasses) {
    std::string out;
    const auto dir = std::filesystem::path(LIDARSCOUT_SOURCE_DIR) / "python";
    const int status =
        test::run_command("cd " + dir.string() + " && /usr/bin/python3 -m lidarscout_train.selftest 2>&1", out);
    EXPECT_EQ(status, 0) << out;
    EXPECT_NE(out.find("ok"), std::string::npos) << out;
}

TEST(PythonTraining, OneStepOnAGeneratedFile) {  // then fine-tuning on two files
    namespace fs = std::filesystem;
    const fs::path dir = fs::temp_directory_path() / ("lidarscout_train_step_" + std::to_string(::getpid()));
    fs::create_directories(dir);
    std::string out;
    ASSERT_EQ(test::run_command(std::string(LIDARSCOUT_CLI) + " train-data " +
                                    (test::surveys_dir() / "ky-woodford-county").string() + " -o " +
                                    (dir / "d.bin").string() + " --texel 2.5 --patches 6 --val-fraction 0 2>&1",
                                out),
              0)
        << out;
    const auto python = std::filesystem::path(LIDARSCOUT_SOURCE_DIR) / "python";
    ASSERT_EQ(
        test::run_command("cd " + python.string() + " && /usr/bin/python3 -m lidarscout_train.train " +
                              (dir / "d.bin").string() + " --out " + (dir / "run").string() +
                              " --epochs 1 --max-steps 1 --batch 4 --width 4 --head-kernel 3 --decoder upsample 2>&1",
                          out),
        0)
        << out;
    EXPECT_TRUE(fs::is_regular_file(dir / "run" / "model.pt"));
    std::ifstream h(dir / "run" / "history.json");
    const auto history = nlohmann::json::parse(h);
    ASSERT_EQ(history.at("epochs").size(), 1u);
    const double loss = history.at("epochs")[0].at("train_loss").get<double>();
    EXPECT_TRUE(std::isfinite(loss) && loss > 0) << loss;
    const auto training_samples = [](const std::string& log) {
        const auto at = log.find("; train ");
        return at == std::string::npos ? -1L : std::stol(log.substr(at + 8));
    };
    const long one_file = training_samples(out);
    ASSERT_GT(one_file, 0) << out;

    // Fine-tuning from that state dict on two files (the recipe's second, 10 m file): the saved
    // configuration overrides the flags, and both files' samples are trained on.
    ASSERT_EQ(test::run_command("cd " + python.string() + " && /usr/bin/python3 -m lidarscout_train.train " +
                                    (dir / "d.bin").string() + " " + (dir / "d.bin").string() + " --init " +
                                    (dir / "run" / "state_dict.pt").string() + " --out " + (dir / "tuned").string() +
                                    " --epochs 1 --max-steps 1 --batch 4 2>&1",
                                out),
              0)
        << out;
    EXPECT_NE(out.find("decoder=upsample width=4"), std::string::npos) << out;
    EXPECT_EQ(training_samples(out), 2 * one_file) << out;
    std::ifstream tuned(dir / "tuned" / "history.json");
    EXPECT_EQ(nlohmann::json::parse(tuned).at("config").at("width").get<int>(), 4);
    EXPECT_TRUE(fs::is_regular_file(dir / "tuned" / "model.pt"));

    // Fine-tuning from a TorchScript model.pt (as the shipped models/heightmap_cnn.pt): the flags
    // name its architecture; flags of another architecture fail instead of training from scratch.
    const auto from_script = [&](const std::string& flags, const std::string& out_name) {
        return test::run_command("cd " + python.string() + " && /usr/bin/python3 -m lidarscout_train.train " +
                                     (dir / "d.bin").string() + " --init " + (dir / "run" / "model.pt").string() +
                                     " --out " + (dir / out_name).string() + " --epochs 1 --max-steps 1 --batch 4 " +
                                     flags + " 2>&1",
                                 out);
    };
    EXPECT_EQ(from_script("--width 4 --head-kernel 3 --decoder upsample --max-per-file 2", "from_script"), 0) << out;
    EXPECT_TRUE(fs::is_regular_file(dir / "from_script" / "model.pt"));
    ASSERT_GT(one_file, 2);
    EXPECT_EQ(training_samples(out), 2) << out;  // --max-per-file: a random subset of the file
    EXPECT_NE(from_script("--width 8 --head-kernel 3 --decoder upsample", "mismatch"), 0) << out;
    EXPECT_NE(out.find("size mismatch"), std::string::npos) << out;
    fs::remove_all(dir);
}

}  // namespace
}  // namespace lidarscout
