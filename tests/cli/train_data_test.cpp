// `lidarscout train-data`: the file is read back by the Python reader (numpy only), its
// records agree with the summary the command printed, and the region split keeps training
// and validation windows apart.
#include <gtest/gtest.h>

#include <filesystem>
#include <unistd.h>

#include "test_data.hpp"

namespace lidarscout {
namespace {

namespace fs = std::filesystem;

nlohmann::json run_json(const std::string& cmd) {
    std::string out;
    EXPECT_EQ(test::run_command(cmd, out), 0) << cmd;
    return nlohmann::json::parse(out);
}

nlohmann::json python_summary(const fs::path& file) {
    return run_json("cd " + (fs::path(LIDARSCOUT_SOURCE_DIR) / "python").string() +
                    " && /usr/bin/python3 -m lidarscout_train.train_data " + file.string());
}

bool windows_overlap(const nlohmann::json& a, const nlohmann::json& b) {
    const double ra = a.at("radius_m").get<double>(), rb = b.at("radius_m").get<double>();
    return std::abs(a.at("centre_x").get<double>() - b.at("centre_x").get<double>()) < ra + rb &&
           std::abs(a.at("centre_y").get<double>() - b.at("centre_y").get<double>()) < ra + rb;
}

TEST(TrainDataCommand, PythonReadsWhatWasWritten) {
    const fs::path out = fs::temp_directory_path() / ("lidarscout_train_" + std::to_string(::getpid()) + ".bin");
    const auto s = run_json(std::string(LIDARSCOUT_CLI) + " train-data --json --texel 5,10 --patches 6 -o " +
                            out.string() + " " + (test::surveys_dir() / "ky-woodford-county").string() + " " +
                            (test::surveys_dir() / "ign-lidar-hd-1km").string() + " 2>/dev/null");
    const auto py = python_summary(out);
    EXPECT_EQ(py.at("count"), s.at("samples"));
    EXPECT_GT(py.at("count").get<int>(), 10);
    EXPECT_EQ(py.at("fields").at("height_in"), nlohmann::json({2, 96, 96}));
    EXPECT_EQ(py.at("fields").at("rgb_in"), nlohmann::json({6, 96, 96}));
    EXPECT_EQ(py.at("fields").at("height_gt"), nlohmann::json({64, 64}));
    EXPECT_EQ(py.at("mask_sum"), py.at("gt_finite"));  // mask = where the ground truth is defined
    EXPECT_TRUE(py.at("height_in_finite").get<bool>());
    EXPECT_LT(py.at("linear_abs_max").get<double>(), 2.0);  // normalised heights
    EXPECT_EQ(py.at("first_sample").at("texel_m"), 5.0);
    EXPECT_EQ(py.at("first_sample").at("dataset"), "ky-woodford-county");
    EXPECT_EQ(py.at("has_rgb")[0], 1);   // Kentucky has colour
    EXPECT_EQ(py.at("has_rgb").back(), 0);  // IGN has none
    fs::remove(out);
}

TEST(TrainDataCommand, RegionSplitKeepsWindowsApart) {
    const fs::path out = fs::temp_directory_path() / ("lidarscout_split_" + std::to_string(::getpid()) + ".bin");
    const auto s =
        run_json(std::string(LIDARSCOUT_CLI) +
                 " train-data --json --texel 2.5 --patches 40 --split-block 700 "
                 "--val-fraction 0.5 -o " +
                 out.string() + " " + (test::surveys_dir() / "ky-woodford-county").string() + " 2>/dev/null");
    EXPECT_GT(s.at("train").get<int>(), 0);
    EXPECT_GT(s.at("validation").get<int>(), 0);
    std::string text;
    // The metadata is the file's tail; read it through the Python reader's loader.
    ASSERT_EQ(test::run_command(
                  "cd " + (fs::path(LIDARSCOUT_SOURCE_DIR) / "python").string() +
                      " && /usr/bin/python3 -c \"import json,sys; from lidarscout_train.train_data import load; "
                      "print(json.dumps(load(sys.argv[1])[1]['samples']))\" " +
                      out.string(),
                  text),
              0);
    const auto samples = nlohmann::json::parse(text);
    for (const auto& a : samples) {
        for (const auto& b : samples) {
            if (a.at("split") != b.at("split")) EXPECT_FALSE(windows_overlap(a, b)) << a.dump() << " " << b.dump();
        }
    }
    fs::remove(out);
}

// Training data without a single sample is an error that says why; no file is written.
TEST(TrainDataCommand, NoSampleIsAnErrorAndNothingIsWritten) {
    const auto out = fs::temp_directory_path() / ("lidarscout_train_none_" + std::to_string(::getpid()) + ".bin");
    std::string text;
    EXPECT_EQ(test::run_command(std::string(LIDARSCOUT_CLI) + " train-data " +
                                    (test::surveys_dir() / "ky-woodford-county").string() + " -o " + out.string() +
                                    " 2>&1", text), 1);
    EXPECT_NE(text.find("training data: no sample in 1 dataset(s)"), std::string::npos) << text;
    EXPECT_FALSE(fs::exists(out));
}

}  // namespace
}  // namespace lidarscout
