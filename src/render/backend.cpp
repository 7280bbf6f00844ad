// Backend choice and the frame drawing shared by the viewer and `lidarscout render`: the same
// checks for both backends, then the CPU passes or the CUDA plugin.
#include "render/backend.hpp"

#include <algorithm>
#include <array>
#include <atomic>
#include <cmath>
#include <cstdio>
#include <memory>
#include <mutex>
#include <string>

#include "core/error.hpp"
#include "core/named_values.hpp"
#include "render/cuda_plugin.hpp"
#include "render/framebuffer.hpp"
#include "render/point_pass.hpp"

namespace lidarscout::render {
namespace {

constexpr std::array<std::string_view, 3> kBackendNames = {"auto", "cpu", "cuda"};
constexpr int kMaxPointSize = 64;
constexpr int kMaxPatchSize = 4096;

// Set when the GPU failed during a frame: later frames are drawn on the CPU.
std::atomic<bool> cuda_failed{false};

void check_patches(std::span<const HeightmapPatch> patches) {
    for (std::size_t i = 0; i < patches.size(); ++i) {
        const HeightmapPatch& p = patches[i];
        const bool size_ok = p.size >= 1 && p.size <= kMaxPatchSize;
        const std::size_t texels = size_ok ? static_cast<std::size_t>(p.size) * p.size : 0;
        if (!size_ok || p.heights.size() != texels || (!p.colours.empty() && p.colours.size() != texels) ||
            !(p.texel_m > 0) || !std::isfinite(p.texel_m) || !std::isfinite(p.origin_x) ||
            !std::isfinite(p.origin_y)) {
            throw Error("heightmap pass: patch " + std::to_string(i) +
                        " needs a size in 1..4096, size x size heights (and colours, or none) and a positive texel "
                        "size");
        }
    }
}

// The checks the CPU passes make, made before either backend draws.
void check_frame(const Camera& camera, std::span<const HeightmapPatch> heightmaps,
                 std::span<const PointLayer> layers, const FrameSettings& s) {
    Framebuffer::check_dimensions(camera.width, camera.height);
    const Palette palette(s.colour);           // throws on bad colour settings
    const HeightmapPassSettings& h = s.heightmaps;
    if (!(h.depth_bias >= 0.0f) || !(h.lod_quad_px > 0.0f) || h.fixed_step < 0 || !(h.skirt_quads >= 0.0f) ||
        !(h.ambient >= 0.0f && h.ambient <= 1.0f)) {
        throw Error("heightmap pass: depth bias, skirt and fixed step must be >= 0, the LOD size > 0 and ambient "
                    "within [0, 1]");
    }
    check_patches(heightmaps);
    for (const PointLayer& layer : layers) {
        if (layer.point_size < 1 || layer.point_size > kMaxPointSize) {
            throw Error("point pass: point size " + std::to_string(layer.point_size) + " is not within 1.." +
                        std::to_string(kMaxPointSize));
        }
    }
    if (!(s.resolve.edl_strength >= 0.0f) || s.resolve.edl_radius_px < 1) {
        throw Error::in_stage("resolve", "EDL strength must be >= 0 and the EDL radius >= 1 pixel");
    }
}

std::size_t count_drawn(const Framebuffer& fb) {
    const std::size_t n = static_cast<std::size_t>(fb.width()) * fb.height();
    return n - static_cast<std::size_t>(std::count(fb.data(), fb.data() + n, kEmpty));
}

// The framebuffer of the last CPU frame, kept for the next one: a fresh 1280 x 720 one is
// 7 MB of new pages, whose page faults cost more than the heightmap pass on some machines.
class SpareFramebuffer {
public:
    std::unique_ptr<Framebuffer> take(int width, int height) {
        std::unique_ptr<Framebuffer> fb;
        {
            std::lock_guard lock(mutex_);
            fb = std::move(spare_);
        }
        if (fb && fb->width() == width && fb->height() == height) {
            fb->clear();
            return fb;
        }
        return std::make_unique<Framebuffer>(width, height);
    }
    void give_back(std::unique_ptr<Framebuffer> fb) {
        std::lock_guard lock(mutex_);
        spare_ = std::move(fb);
    }

private:
    std::mutex mutex_;
    std::unique_ptr<Framebuffer> spare_;
};

SpareFramebuffer spare_framebuffer;

FrameImage draw_frame_cpu(const Camera& camera, std::span<const HeightmapPatch> heightmaps,
                          std::span<const PointLayer> layers, const FrameSettings& settings, ThreadPool& pool) {
    std::unique_ptr<Framebuffer> owned = spare_framebuffer.take(camera.width, camera.height);
    Framebuffer& fb = *owned;
    if (!heightmaps.empty()) {
        HeightmapPassSettings hs = settings.heightmaps;
        hs.colour = settings.colour;
        draw_heightmaps(fb, camera, heightmaps, hs, pool);
    }
    for (const PointLayer& layer : layers) {
        if (layer.batches.empty()) continue;
        PointPassSettings ps;
        ps.colour = settings.colour;
        ps.point_size = layer.point_size;
        ps.adaptive_size = layer.adaptive_size;
        ps.chunk_points = settings.chunk_points;
        ps.filter = settings.filter;
        draw_points(fb, camera, layer.batches, ps, pool);
    }
    FrameImage frame{resolve(fb, settings.resolve, pool), count_drawn(fb)};
    spare_framebuffer.give_back(std::move(owned));
    return frame;
}

bool cuda_usable() { return !cuda_failed.load() && cuda::unavailable_reason().empty(); }

}  // namespace

Backend parse_backend(std::string_view name) { return parse_named<Backend>(kBackendNames, name, "backend"); }

std::string_view backend_name(Backend backend) { return name_of(kBackendNames, backend); }

std::string cuda_unavailable_reason() {
    if (cuda_failed.load()) return "the GPU failed during a frame";
    return cuda::unavailable_reason();
}

std::string cuda_device_name() { return cuda_unavailable_reason().empty() ? cuda::device_name() : std::string(); }

BackendChoice choose_backend(Backend requested) {
    if (requested == Backend::Cpu) return {Backend::Cpu, {}};
    const std::string reason = cuda_unavailable_reason();
    if (reason.empty()) return {Backend::Cuda, {}};
    const std::string note = "CUDA backend unavailable: " + reason;
    if (requested == Backend::Cuda) throw Error(note);
    return {Backend::Cpu, note};
}

FrameImage draw_frame(Backend backend, const Camera& camera, std::span<const HeightmapPatch> heightmaps,
                      std::span<const PointLayer> layers, const FrameSettings& settings, ThreadPool& pool) {
    check_frame(camera, heightmaps, layers, settings);
    if (backend == Backend::Cpu || (backend == Backend::Auto && !cuda_usable())) {
        return draw_frame_cpu(camera, heightmaps, layers, settings, pool);
    }
    if (backend == Backend::Cuda) choose_backend(Backend::Cuda);  // throws when unavailable
    try {
        return cuda::draw_frame(camera, heightmaps, layers, settings);
    } catch (const Error& e) {
        if (!cuda_failed.exchange(true)) {
            std::fprintf(stderr, "lidarscout: %s; drawing on the CPU from now on\n", e.what());
        }
        return draw_frame_cpu(camera, heightmaps, layers, settings, pool);
    }
}

}  // namespace lidarscout::render
