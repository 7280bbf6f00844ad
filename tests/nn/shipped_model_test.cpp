// The shipped model (models/heightmap_cnn.pt), found without flags, through the C++ runner: a
// batch of real patches gives finite outputs of the right shape, a planar input comes back
// planar, and `eval --methods linear,cnn` scores it on every patch linear is scored on.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <memory>
#include <span>

#include "dataset/dataset.hpp"
#include "nn/heightmap_network.hpp"
#include "nn/network_io.hpp"
#include "recon/interpolation.hpp"
#include "pipelines/survey_samples.hpp"
#include "core/thread_pool.hpp"
#include "test_data.hpp"

namespace lidarscout::nn {
namespace {

const HeightmapNetwork& shipped() {
    static const auto net = std::make_unique<HeightmapNetwork>(HeightmapNetwork::load(default_model_path(), 2));
    return *net;
}

TEST(ShippedModel, FoundWithoutFlags) {
    const std::string path = default_model_path();
    EXPECT_NE(path.find(kDefaultModelName), std::string::npos);
    EXPECT_EQ(shipped().path(), path);
}

// A tilted plane (the same in the nearest and linear inputs), uniform colour.
std::vector<float> plane_input(double a, double b, float colour) {
    constexpr int w = 96;
    std::vector<float> in(input_size(w));
    const std::size_t plane = std::size_t(w) * w;
    for (int r = 0; r < w; ++r) {
        for (int c = 0; c < w; ++c) {
            const float h = static_cast<float>(a * (c - 47.5) / 48.0 + b * (r - 47.5) / 48.0);
            in[r * w + c] = in[plane + r * w + c] = h;
            for (int ch = 2; ch < 8; ++ch) in[ch * plane + r * w + c] = colour;
        }
    }
    return in;
}

// Least-squares plane h = p0 + p1 * col + p2 * row through a 64 x 64 height plane; returns the
// largest distance of a texel from it.
double plane_fit_residual(std::span<const float> h) {
    double m[3][4] = {};
    for (int r = 0; r < 64; ++r) {
        for (int c = 0; c < 64; ++c) {
            const double v[3] = {1.0, double(c), double(r)};
            for (int i = 0; i < 3; ++i) {
                for (int j = 0; j < 3; ++j) m[i][j] += v[i] * v[j];
                m[i][3] += v[i] * h[r * 64 + c];
            }
        }
    }
    for (int i = 0; i < 3; ++i) {  // Gauss-Jordan (the matrix is well conditioned)
        for (int k = 0; k < 3; ++k) {
            if (k == i) continue;
            const double f = m[k][i] / m[i][i];
            for (int j = 0; j < 4; ++j) m[k][j] -= f * m[i][j];
        }
    }
    const double p0 = m[0][3] / m[0][0], p1 = m[1][3] / m[1][1], p2 = m[2][3] / m[2][2];
    double worst = 0;
    for (int r = 0; r < 64; ++r) {
        for (int c = 0; c < 64; ++c) worst = std::max(worst, std::abs(h[r * 64 + c] - (p0 + p1 * c + p2 * r)));
    }
    return worst;
}

TEST(ShippedModel, PlanarInputComesBackPlanar) {
    const double a = 0.05, b = -0.03;  // 24 m and 14 m of slope across a 10 m-texel window (radius 480 m)
    const auto out = shipped().run(plane_input(a, b, 0.4f), 1, 96);
    ASSERT_EQ(out.size(), output_size(64));
    double mean_offset = 0, worst_colour = 0;
    for (int r = 0; r < 64; ++r) {
        for (int c = 0; c < 64; ++c) {
            mean_offset += out[r * 64 + c] - (a * (c + 16 - 47.5) / 48.0 + b * (r + 16 - 47.5) / 48.0);
            for (int ch = 1; ch < 4; ++ch) {
                worst_colour = std::max(worst_colour, std::abs(out[ch * 4096 + r * 64 + c] - 0.4));
            }
        }
    }
    mean_offset /= 4096.0;
    const double residual = plane_fit_residual(std::span(out).first(4096));
    std::printf("plane: mean offset %.4f, largest distance from the best-fit plane %.4f (of the radius)\n",
                mean_offset, residual);
    // Normalised units: 0.002 of the radius is 0.96 m at 10 m texels, on a plane 38 m high.
    EXPECT_LT(residual, 0.002) << "largest distance from the best-fit plane";
    // The shipped model lifts a bare plane by ~0.001 of the radius (models/README.md, known
    // flaws): allowed up to 0.005 here, so that a model that moves planes further fails.
    EXPECT_LT(std::abs(mean_offset), 0.005) << "mean offset from the input plane";
    EXPECT_LT(worst_colour, 0.05);
}

TEST(ShippedModel, BatchOfRealPatchesIsFinite) {
    const auto ds = dataset::open_dataset({(test::surveys_dir() / "ky-jmo335-eastern-kentucky").string()});
    recon::PatchSpec spec;
    spec.texel_m = 2.5;
    const pipelines::Lattice l = pipelines::lattice_for(ds, spec);
    ThreadPool pool(2);
    const auto s = pipelines::sample_survey(ds, {{l, pipelines::auto_stride(ds, spec), {}}}, pool);
    std::vector<recon::InterpolatedPatch> patches;
    for (const auto cell : s.samples[0].chunk_points->cells()) {
        auto ip =
            recon::interpolate_patch(recon::make_patch_points(*s.samples[0].chunk_points, cell, {spec, 25, true}));
        if (ip.status == recon::PatchStatus::Ok) patches.push_back(std::move(ip));
        if (patches.size() == 5) break;
    }
    ASSERT_EQ(patches.size(), 5u);
    std::vector<const recon::InterpolatedPatch*> batch;
    for (const auto& p : patches) batch.push_back(&p);
    const auto out = shipped().infer(batch, true);
    ASSERT_EQ(out.size(), 5u);
    for (std::size_t i = 0; i < out.size(); ++i) {
        EXPECT_EQ(out[i].method, recon::Method::Cnn);
        ASSERT_EQ(out[i].height.size, 64);
        ASSERT_EQ(out[i].rgb.channels, 3);
        for (const float v : out[i].height.values) ASSERT_TRUE(std::isfinite(v)) << i;
        for (const float v : out[i].rgb.values) ASSERT_TRUE(v >= 0.0f && v <= 1.0f) << i;
        // Close to its linear input (the network corrects it, it does not replace it).
        const auto lin = recon::crop_centre(patches[i].height_linear, 64);
        double sq = 0;
        for (std::size_t k = 0; k < lin.values.size(); ++k) sq += std::pow(out[i].height.values[k] - lin.values[k], 2);
        EXPECT_LT(std::sqrt(sq / lin.values.size()), 0.1) << i;
    }
}

TEST(ShippedModel, EvalScoresCnnOnTheSamePatches) {
    std::string out;
    ASSERT_EQ(
        test::run_command(std::string(LIDARSCOUT_CLI) + " eval --json --methods linear,cnn --patches 6 --texel 5 " +
                              (test::surveys_dir() / "ky-woodford-county").string() + " 2>/dev/null",
                          out),
        0);
    const auto j = nlohmann::json::parse(out);
    const auto& m = j.at("methods");
    EXPECT_EQ(m.at("cnn").at("patches"), m.at("linear").at("patches"));
    EXPECT_GT(m.at("cnn").at("patches").get<int>(), 0);
    EXPECT_GT(m.at("cnn").at("rmse_m_mean").get<double>(), 0.0);
    EXPECT_GT(m.at("cnn").at("psnr_db_mean").get<double>(), 10.0);
    EXPECT_NE(j.at("model").get<std::string>().find(kDefaultModelName), std::string::npos);
}

}  // namespace
}  // namespace lidarscout::nn
