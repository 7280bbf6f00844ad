// The cases on which the CUDA backend must draw what the CPU draws: one scene (textured and
// untextured heightmap patches with a hole, large triangles close to the camera, point layers of
// two sizes) in every colour mode, with point filters (classes, return kinds, intensity), the
// bare-earth tint, adaptive point sizes over a real (non-zero) spacing, the heightmap pass alone,
// and data kept on the GPU between frames. Shared by tests/render/cuda_backend_test.cpp (the
// suite, wherever it runs) and bench/gpu_harness.cpp (scripts/gpu_checks.sh, on a GPU machine).
//
// Each case has a CPU side, checked everywhere: its frame draws at least half the pixels and,
// where the case has a control (the same scene without what the case checks), differs from the
// control's frame in more pixels than the GPU comparison forgives, so that a GPU which ignored
// the feature would fail. Its GPU side, where the CUDA backend is available: at least 99% of the
// pixels within 2 levels per channel of the CPU's and the drawn pixel counts within 0.2% of the
// image; a kept case also draws frames from the data kept on the GPU that equal its first frame.
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "core/thread_pool.hpp"
#include "render/backend.hpp"

namespace lidarscout::render::gpu_cases {

// The GPU comparison's tolerance (as tests/render/cuda_backend_test.cpp has always used).
inline constexpr int kMaxLevelDifference = 2;          // per channel
inline constexpr double kMinCloseShare = 0.99;         // of the pixels
inline constexpr double kMaxDrawnDifferenceShare = 0.002;  // of the image's pixels
// A case's frame differs from its control's in at least this share of pixels (beyond the level
// tolerance): well over the 1% the comparison forgives.
inline constexpr double kMinControlChangedShare = 0.05;

// What a case draws; it owns the data its patches and batches point into (so it stays put).
struct Scene {
    Scene() = default;
    Scene(const Scene&) = delete;
    Scene& operator=(const Scene&) = delete;

    std::vector<std::vector<float>> heights;
    std::vector<std::vector<std::uint32_t>> colours;
    std::vector<HeightmapPatch> patches;
    std::vector<PointAttr> points_a, points_b;
    std::vector<PointBatch> chunk, full;
    std::vector<PointLayer> layers;
    FrameSettings settings;
    Camera camera;
};

struct Case {
    std::string_view name;    // letters, digits and '_' (a GoogleTest parameter name)
    std::string_view checks;  // what it checks, for the summary
    void (*build)(Scene& scene);
    void (*control)(Scene& scene);  // takes the checked feature out of a built scene; null: none
    int kept_frames = 0;            // > 0: keys on every batch and patch, and this many frames drawn again
};

// Every case, in the order the summary lists them.
std::span<const Case> cases();
// The case of that name; throws lidarscout::Error naming the known ones otherwise.
const Case& find_case(std::string_view name);

// The share of pixels whose channels all differ by at most `levels`.
double share_close(const RgbaImage& a, const RgbaImage& b, int levels = kMaxLevelDifference);

struct CpuSide {
    FrameImage frame;
    double drawn_share = 0;
    double control_changed_share = -1;  // -1: no control
    std::string failure;                // empty: passed
};
CpuSide draw_on_cpu(const Case& c, ThreadPool& pool);

struct GpuSide {
    RgbaImage image;  // the GPU's first frame
    double close_share = 0, psnr_db = 0;
    std::size_t drawn_pixels = 0;
    int kept_frames_equal = 0;  // of kept_frames
    std::string failure;        // empty: passed
};
// Needs the CUDA backend (cuda_unavailable_reason() empty); `cpu` is draw_on_cpu's result.
GpuSide draw_on_gpu(const Case& c, const CpuSide& cpu, ThreadPool& pool);

// A binary PPM of the image (alpha dropped), to look at a failure.
void write_ppm(const std::string& path, const RgbaImage& image);

}  // namespace lidarscout::render::gpu_cases
