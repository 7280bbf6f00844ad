// The CUDA backend draws what the CPU draws, on every case of gpu_cases.hpp: every colour mode,
// eye-dome lighting, point filters, the bare-earth tint, adaptive point sizes over a real
// spacing, the heightmap pass alone and data kept on the GPU. The CPU side of each case (its
// frame draws, and differs from its control's) is checked everywhere; the GPU side is skipped,
// with the reason, where the CUDA backend is unavailable (scripts/gpu_checks.sh runs the same
// cases on a GPU machine through bench/gpu_harness.cpp).
#include <gtest/gtest.h>

#include <string>

#include "core/error.hpp"
#include "render/backend.hpp"
#include "render/gpu_cases.hpp"

namespace lidarscout::render {
namespace {

class CudaBackend : public ::testing::TestWithParam<gpu_cases::Case> {};

TEST_P(CudaBackend, DrawsWhatTheCpuDraws) {
    const gpu_cases::Case& c = GetParam();
    ThreadPool pool(2);
    const gpu_cases::CpuSide cpu = gpu_cases::draw_on_cpu(c, pool);
    EXPECT_EQ(cpu.failure, "") << c.checks;
    if (c.control) {
        EXPECT_GE(cpu.control_changed_share, gpu_cases::kMinControlChangedShare);
    }
    const std::string reason = cuda_unavailable_reason();
    if (!reason.empty()) GTEST_SKIP() << "CUDA backend unavailable: " << reason;
    const gpu_cases::GpuSide gpu = gpu_cases::draw_on_gpu(c, cpu, pool);
    EXPECT_EQ(gpu.failure, "") << c.checks << ", on " << cuda_device_name();
    EXPECT_GE(gpu.close_share, gpu_cases::kMinCloseShare);
}

// The tolerance sees a difference: an image against itself is close, against a darker copy not.
TEST(CudaBackendCompare, ShareCloseCountsPixelsBeyondTheLevels) {
    ThreadPool pool(2);
    const gpu_cases::CpuSide cpu = gpu_cases::draw_on_cpu(gpu_cases::find_case("heightmaps"), pool);
    RgbaImage darker = cpu.frame.image;
    for (std::size_t i = 0; i < darker.pixels.size(); i += 2) darker.pixels[i] &= 0xFF000000u;
    EXPECT_EQ(gpu_cases::share_close(cpu.frame.image, cpu.frame.image), 1.0);
    EXPECT_LT(gpu_cases::share_close(cpu.frame.image, darker), 0.75);
    EXPECT_THROW(gpu_cases::find_case("vulkan"), Error);
}

INSTANTIATE_TEST_SUITE_P(Cases, CudaBackend, ::testing::ValuesIn(gpu_cases::cases().begin(), gpu_cases::cases().end()),
                         [](const auto& info) { return std::string(info.param.name); });

}  // namespace
}  // namespace lidarscout::render
