// The released model's conventions (nn/released_model.hpp): height units against the
// reference viewer's formulas, and the wiring (input names, NaN fill, centre, 96 -> 64 crop,
// denormalisation) through a stand-in TorchScript model whose output is predictable
// (python/lidarscout_train/released_reference.py: 1.5 x the linear input's centre crop).
#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <filesystem>

#include "core/error.hpp"
#include "nn/released_model.hpp"
#include "test_data.hpp"

namespace lidarscout::nn {
namespace {

namespace fs = std::filesystem;

// Written once per process.
const fs::path& stand_in_model() {
    static const fs::path file = [] {
        const fs::path f = fs::temp_directory_path() / ("lidarscout_released_" + std::to_string(::getpid()) + ".pt");
        std::string out;
        const std::string python = (fs::path(LIDARSCOUT_SOURCE_DIR) / "python").string();
        const std::string cmd = "/usr/bin/python3 -m lidarscout_train.released_reference " + f.string() + " 2>&1";
        const int rc = test::run_command("cd " + python + " && " + cmd, out);
        EXPECT_EQ(rc, 0) << out;
        return f;
    }();
    return file;
}

TEST(ReleasedModel, HeightUnitsFollowTheReferenceViewer) {
    // 10 m texels: our radius 480 m; the reference's input radius sqrt(2)/2 * 10 * 96 * 1.5 m
    // and output radius sqrt(2)/2 * 10 * 64 * 1.5 m, both with the stability factor 10.
    const double r = 480, r_in = std::sqrt(0.5) * 10 * 96 * 1.5, r_out = std::sqrt(0.5) * 10 * 64 * 1.5;
    const float centre = 0.05f;
    EXPECT_NEAR(to_released_height(static_cast<float>(centre + 100.0 / r), centre), 100.0 / r_in * 10, 1e-5);
    EXPECT_NEAR(from_released_height(1.0f, centre), centre + 1.0 / 10 * r_out / r, 1e-6);
}

TEST(ReleasedModel, StandInReturnsTheLinearHeightsThroughTheConventions) {
    const auto model = load_released_model(stand_in_model().string(), 1);
    recon::InterpolatedPatch p;
    p.status = recon::PatchStatus::Ok;
    p.height_nearest = recon::Image(96, 1);
    p.height_linear = recon::Image(96, 1);
    for (int y = 0; y < 96; ++y) {
        for (int x = 0; x < 96; ++x) {
            p.height_nearest.at(y, x) = 0.5f;
            p.height_linear.at(y, x) = 0.01f * x - 0.002f * y;
        }
    }
    p.height_linear.at(40, 30) = std::nanf("");  // outside the hull: the nearest height goes in
    p.mean_height = 0.2f;
    const recon::InterpolatedPatch* batch[] = {&p, &p};
    const auto out = infer_released(*model, batch);
    ASSERT_EQ(out.size(), 2u);
    EXPECT_EQ(out[1].method, recon::Method::Released);
    ASSERT_EQ(out[1].height.size, 64);
    EXPECT_TRUE(out[1].rgb.empty());
    for (int y = 0; y < 64; ++y) {
        for (int x = 0; x < 64; ++x) {
            const float want = (y == 24 && x == 14) ? 0.5f : p.height_linear.at(y + 16, x + 16);
            ASSERT_NEAR(out[1].height.at(y, x), want, 1e-5) << y << "," << x;
        }
    }
}

TEST(ReleasedModel, MissingFileIsAnError) {
    EXPECT_THROW(load_released_model("/nonexistent/ipes_cnn.pt"), Error);
}

}  // namespace
}  // namespace lidarscout::nn
