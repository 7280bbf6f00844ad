// The CUDA backend draws what the CPU draws: one scene (textured and untextured heightmap
// patches with holes, large triangles close to the camera, point layers of two sizes) in every
// colour mode and with eye-dome lighting, on both backends; at least 99% of the pixels within
// 2 levels per channel. Skipped, with the reason, where the CUDA backend is unavailable.
// With LIDARSCOUT_TEST_IMAGES=DIR both images are written there as PPM files to compare by eye.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <fstream>
#include <string>
#include <vector>

#include "render/backend.hpp"
#include "render/framebuffer.hpp"

namespace lidarscout::render {
namespace {

constexpr double kOx = 600'000.0, kOy = 4'200'000.0;
constexpr int kSize = 64;

struct TestScene {
    std::vector<std::vector<float>> heights;
    std::vector<std::vector<std::uint32_t>> colours;
    std::vector<HeightmapPatch> patches;
    std::vector<PointAttr> points_a, points_b;
    std::vector<PointBatch> chunk, full;
};

float terrain(double x, double y) { return static_cast<float>(120.0 + 15.0 * std::sin(x / 90.0) * std::cos(y / 70.0)); }

// A 2 x 2 block of 640 m patches; patch 1 is untextured, patch 3 has a hole.
void add_patches(TestScene& s) {
    for (int p = 0; p < 4; ++p) {
        const double ox = kOx + (p % 2) * 640.0, oy = kOy + (p / 2) * 640.0;
        auto& h = s.heights.emplace_back(kSize * kSize);
        auto& c = s.colours.emplace_back(p == 1 ? 0 : kSize * kSize);
        for (int j = 0; j < kSize; ++j) {
            for (int i = 0; i < kSize; ++i) {
                const std::size_t t = static_cast<std::size_t>(j) * kSize + i;
                h[t] = terrain(ox + (i + 0.5) * 10.0, oy + (j + 0.5) * 10.0);
                if (p == 3 && i > 20 && i < 30 && j > 10 && j < 25) h[t] = NAN;
                if (!c.empty()) {
                    c[t] = pack_rgba(static_cast<std::uint8_t>(i * 4), static_cast<std::uint8_t>(j * 4), 90);
                }
            }
        }
    }
    for (int p = 0; p < 4; ++p) {
        s.patches.push_back({kOx + (p % 2) * 640.0, kOy + (p / 2) * 640.0, 10.0, kSize, s.heights[p], s.colours[p]});
    }
}

void add_points(TestScene& s) {
    for (int k = 0; k < 60'000; ++k) {
        const double x = (k % 300) * 4.0, y = (k / 300) * 6.0;
        PointAttr p;
        p.dx = static_cast<float>(x), p.dy = static_cast<float>(y);
        p.dz = terrain(kOx + 40.0 + x, kOy + 40.0 + y) + 2.0f + (k % 7) - 100.0f;
        p.r = static_cast<std::uint8_t>(k), p.g = static_cast<std::uint8_t>(k >> 3), p.b = 200;
        p.intensity = static_cast<std::uint16_t>(k * 13), p.classification = static_cast<std::uint8_t>(k % 25);
        (k % 3 ? s.points_a : s.points_b).push_back(p);
    }
    s.chunk.push_back({kOx + 40.0, kOy + 40.0, 100.0, s.points_b});
    s.full.push_back({kOx + 40.0, kOy + 40.0, 100.0, s.points_a});
}

// Close over the patches, looking north-east and down: near triangles are large on screen.
Camera test_camera() {
    Camera c;
    c.x = kOx + 300.0, c.y = kOy + 200.0, c.z = 180.0;
    c.yaw_deg = 30, c.pitch_deg = -25, c.width = 640, c.height = 400, c.near_m = 1.0, c.far_m = 5000.0;
    return c;
}

// The share of pixels whose channels all differ by at most 2 levels.
double share_close(const RgbaImage& a, const RgbaImage& b) {
    std::size_t close = 0;
    for (std::size_t i = 0; i < a.pixels.size(); ++i) {
        const std::uint32_t p = a.pixels[i], q = b.pixels[i];
        const auto d = [](int x, int y) { return std::abs(x - y); };
        close += d(red(p), red(q)) <= 2 && d(green(p), green(q)) <= 2 && d(blue(p), blue(q)) <= 2;
    }
    return static_cast<double>(close) / a.pixels.size();
}

// A binary PPM of the image (alpha dropped), for looking at a failure.
void write_ppm(const std::string& path, const RgbaImage& image) {
    std::ofstream out(path, std::ios::binary);
    out << "P6\n" << image.width << ' ' << image.height << "\n255\n";
    for (const std::uint32_t p : image.pixels) {
        const char rgb[3] = {static_cast<char>(red(p)), static_cast<char>(green(p)), static_cast<char>(blue(p))};
        out.write(rgb, 3);
    }
}

class CudaBackend : public ::testing::TestWithParam<ColourMode> {};

TEST_P(CudaBackend, DrawsWhatTheCpuDraws) {
    const std::string reason = cuda_unavailable_reason();
    if (!reason.empty()) GTEST_SKIP() << "CUDA backend unavailable: " << reason;
    TestScene scene;
    add_patches(scene);
    add_points(scene);
    const PointLayer layers[] = {{scene.chunk, 3}, {scene.full, 1}};
    FrameSettings settings;
    settings.colour.mode = GetParam();
    settings.colour.z_min = 90, settings.colour.z_max = 160;
    settings.resolve.edl_strength = GetParam() == ColourMode::Rgb ? 1.0f : 0.0f;
    settings.chunk_points = 5'000;
    ThreadPool pool(2);
    const Camera cam = test_camera();
    const FrameImage cpu = draw_frame(Backend::Cpu, cam, scene.patches, layers, settings, pool);
    const FrameImage gpu = draw_frame(Backend::Cuda, cam, scene.patches, layers, settings, pool);
    if (const char* dir = std::getenv("LIDARSCOUT_TEST_IMAGES"); dir && *dir) {
        const std::string mode(colour_mode_name(GetParam()));
        write_ppm(std::string(dir) + "/cuda_test_" + mode + "_cpu.ppm", cpu.image);
        write_ppm(std::string(dir) + "/cuda_test_" + mode + "_gpu.ppm", gpu.image);
    }
    ASSERT_EQ(gpu.image.width, cpu.image.width);
    ASSERT_EQ(gpu.image.pixels.size(), cpu.image.pixels.size());
    EXPECT_GT(cpu.drawn_pixels, cpu.image.pixels.size() / 2);
    EXPECT_NEAR(static_cast<double>(gpu.drawn_pixels), static_cast<double>(cpu.drawn_pixels),
                0.002 * cpu.image.pixels.size());
    EXPECT_GE(share_close(cpu.image, gpu.image), 0.99) << "on " << cuda_device_name();
}

// Bare-earth tint (render::PatchTint, ABI 6): a patch tinted whole and one whose left half is
// marked (colour alpha below 255) change the CPU's frame, and draw on the GPU what they draw there.
TEST(CudaBackendTint, TintedPatchesDrawWhatTheCpuDraws) {
    TestScene scene;
    add_patches(scene);
    for (int j = 0; j < kSize; ++j) {
        for (int i = 0; i < kSize / 2; ++i) {
            std::uint32_t& c = scene.colours[2][static_cast<std::size_t>(j) * kSize + i];
            c = (c & 0x00FFFFFFu) | (128u << 24);
        }
    }
    std::vector<HeightmapPatch> tinted = scene.patches;
    tinted[0].tint = PatchTint::All;
    tinted[2].tint = PatchTint::Marked;
    FrameSettings settings;
    settings.colour.mode = ColourMode::Rgb;
    ThreadPool pool(2);
    const Camera cam = test_camera();
    const FrameImage plain = draw_frame(Backend::Cpu, cam, scene.patches, {}, settings, pool);
    const FrameImage cpu = draw_frame(Backend::Cpu, cam, tinted, {}, settings, pool);
    EXPECT_LT(share_close(plain.image, cpu.image), 0.9);  // the tint covers much of the view
    const std::string reason = cuda_unavailable_reason();
    if (!reason.empty()) GTEST_SKIP() << "CUDA backend unavailable: " << reason;
    const FrameImage gpu = draw_frame(Backend::Cuda, cam, tinted, {}, settings, pool);
    EXPECT_GE(share_close(cpu.image, gpu.image), 0.99) << "on " << cuda_device_name();
}

// Batches and patches with cache keys are kept on the GPU: later frames draw them from there,
// and every frame is the image drawn from data uploaded with the frame.
TEST(CudaBackendKept, KeptDataDrawsWhatUploadedDataDraws) {
    const std::string reason = cuda_unavailable_reason();
    if (!reason.empty()) GTEST_SKIP() << "CUDA backend unavailable: " << reason;
    TestScene scene;
    add_patches(scene);
    add_points(scene);
    std::vector<PointBatch> chunk = scene.chunk, full = scene.full;
    for (PointBatch& b : chunk) b.cache_key = new_cache_key();
    for (PointBatch& b : full) b.cache_key = new_cache_key();
    std::vector<HeightmapPatch> patches = scene.patches;
    for (HeightmapPatch& p : patches) p.cache_key = new_cache_key();
    const PointLayer uploaded[] = {{scene.chunk, 3}, {scene.full, 1}};
    const PointLayer kept[] = {{chunk, 3}, {full, 1}};
    FrameSettings settings;
    settings.chunk_points = 5'000;
    ThreadPool pool(2);
    const Camera cam = test_camera();
    const FrameImage reference = draw_frame(Backend::Cuda, cam, scene.patches, uploaded, settings, pool);
    for (int frame = 0; frame < 3; ++frame) {
        const FrameImage image = draw_frame(Backend::Cuda, cam, patches, kept, settings, pool);
        EXPECT_EQ(image.image.pixels, reference.image.pixels) << "frame " << frame;
    }
}

INSTANTIATE_TEST_SUITE_P(Modes, CudaBackend,
                         ::testing::Values(ColourMode::Rgb, ColourMode::Elevation, ColourMode::Intensity,
                                           ColourMode::Classification),
                         [](const auto& info) { return std::string(colour_mode_name(info.param)); });

}  // namespace
}  // namespace lidarscout::render
