// Rasterizer backends: parsing and naming, `auto` falling back to the CPU with the reason when
// the CUDA backend is unavailable, `cuda` then failing with one line, draw_frame on the CPU
// matching the passes it runs, and the CLI's --backend option.
#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

#include "core/error.hpp"
#include "render/backend.hpp"
#include "render/framebuffer.hpp"
#include "render/point_pass.hpp"
#include "test_data.hpp"

namespace lidarscout::render {
namespace {

TEST(RenderBackend, ParsesAndNamesEveryBackend) {
    for (const Backend b : {Backend::Auto, Backend::Cpu, Backend::Cuda}) EXPECT_EQ(parse_backend(backend_name(b)), b);
    EXPECT_EQ(parse_backend("cuda"), Backend::Cuda);
    try {
        parse_backend("vulkan");
        FAIL() << "no error for an unknown backend";
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find("auto, cpu, cuda"), std::string::npos) << e.what();
    }
}

TEST(RenderBackend, CpuIsAlwaysCpu) {
    const BackendChoice c = choose_backend(Backend::Cpu);
    EXPECT_EQ(c.backend, Backend::Cpu);
    EXPECT_TRUE(c.note.empty());
}

TEST(RenderBackend, AutoUsesCudaOnlyWhenAvailableAndSaysWhyNot) {
    const std::string reason = cuda_unavailable_reason();
    const BackendChoice c = choose_backend(Backend::Auto);
    if (reason.empty()) {
        EXPECT_EQ(c.backend, Backend::Cuda);
        EXPECT_FALSE(cuda_device_name().empty());
    } else {
        EXPECT_EQ(c.backend, Backend::Cpu);
        EXPECT_EQ(c.note, "CUDA backend unavailable: " + reason);
        EXPECT_EQ(reason.find('\n'), std::string::npos) << reason;
    }
}

TEST(RenderBackend, CudaWhenUnavailableIsAOneLineError) {
    const std::string reason = cuda_unavailable_reason();
    if (reason.empty()) GTEST_SKIP() << "the CUDA backend is available here (" << cuda_device_name() << ")";
    try {
        choose_backend(Backend::Cuda);
        FAIL() << "no error for an unavailable CUDA backend";
    } catch (const Error& e) {
        const std::string what = e.what();
        EXPECT_EQ(what, "CUDA backend unavailable: " + reason);
        EXPECT_EQ(what.find('\n'), std::string::npos);
    }
}

// draw_frame on the CPU is exactly the passes it stands for.
TEST(RenderBackend, CpuFrameIsThePointPassAndResolve) {
    Camera cam;
    cam.x = 500'000.0, cam.y = 5'000'000.0, cam.z = 100.0, cam.width = 80, cam.height = 60;
    std::vector<PointAttr> points;
    for (int i = 0; i < 200; ++i) {
        PointAttr p;
        p.dx = static_cast<float>(i % 20) - 10.0f, p.dy = 50.0f + static_cast<float>(i / 20), p.dz = -5.0f;
        p.r = static_cast<std::uint8_t>(i), p.g = 100, p.b = 200;
        points.push_back(p);
    }
    const PointBatch batch{cam.x, cam.y, cam.z, points};
    const PointLayer layer{std::span<const PointBatch>(&batch, 1), 2};
    FrameSettings settings;
    settings.resolve.edl_strength = 1.0f;
    ThreadPool pool(2);
    const FrameImage frame = draw_frame(Backend::Cpu, cam, {}, std::span<const PointLayer>(&layer, 1), settings, pool);

    Framebuffer fb(cam.width, cam.height);
    PointPassSettings ps;
    ps.point_size = 2;
    draw_points(fb, cam, std::span<const PointBatch>(&batch, 1), ps, pool);
    const RgbaImage expected = resolve(fb, settings.resolve, pool);
    EXPECT_EQ(frame.image.pixels, expected.pixels);
    EXPECT_GT(frame.drawn_pixels, 20u);
}

TEST(RenderBackend, BadPointSizeIsRejectedOnEveryBackend) {
    Camera cam;
    cam.width = 16, cam.height = 16;
    const PointLayer layer{{}, 0};
    ThreadPool pool(1);
    for (const Backend b : {Backend::Cpu, Backend::Auto}) {
        EXPECT_THROW(draw_frame(b, cam, {}, std::span<const PointLayer>(&layer, 1), FrameSettings{}, pool), Error);
    }
}

// `lidarscout render --backend cuda` where CUDA is unavailable: exit 1 and one line naming
// the reason, before any file is read.
TEST(RenderBackend, RenderCommandCudaUnavailableIsOneLine) {
    const std::string reason = cuda_unavailable_reason();
    if (reason.empty()) GTEST_SKIP() << "the CUDA backend is available here";
    std::string out;
    const int rc = test::run_command(std::string(LIDARSCOUT_CLI) +
                                         " render /nonexistent.laz -o /nonexistent.png --backend cuda 2>&1",
                                     out);
    EXPECT_EQ(rc, 1) << out;
    EXPECT_EQ(out.find("lidarscout: CUDA backend unavailable: "), 0u) << out;
    EXPECT_EQ(out.find('\n'), out.size() - 1) << out;
}

TEST(RenderBackend, RenderCommandRejectsAnUnknownBackend) {
    std::string out;
    const int rc = test::run_command(std::string(LIDARSCOUT_CLI) +
                                         " render /nonexistent.laz -o /nonexistent.png --backend opengl 2>&1",
                                     out);
    EXPECT_EQ(rc, 1) << out;
    EXPECT_NE(out.find("unknown backend 'opengl'"), std::string::npos) << out;
}

}  // namespace
}  // namespace lidarscout::render
