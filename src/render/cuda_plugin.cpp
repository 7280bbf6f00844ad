// Opening the CUDA rasterizer plugin with dlopen and drawing a frame with it: the host side
// prepares what the kernels need in the form of raster_abi.h (camera transforms rebuilt per
// batch origin in double, then float, as the CPU point pass does per chunk; colour tables
// from the CPU Palette), so both backends start from the same numbers.
#include "render/cuda_plugin.hpp"


#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdlib>
#include <mutex>

#include "core/error.hpp"
#include "core/plugin_paths.hpp"
#include "render/cuda/raster_abi.h"
#include "render/point_pass.hpp"

#ifndef LIDARSCOUT_BUILD_DIR
#define LIDARSCOUT_BUILD_DIR ""
#endif

namespace lidarscout::render::cuda {

static_assert(sizeof(LsrPoint) == sizeof(PointAttr));
static_assert(offsetof(LsrPoint, dz) == offsetof(PointAttr, dz));
static_assert(offsetof(LsrPoint, classification) == offsetof(PointAttr, classification));
static_assert(offsetof(LsrPoint, intensity) == offsetof(PointAttr, intensity));
static_assert(offsetof(LsrPoint, returns) == offsetof(PointAttr, returns));

namespace {

struct Plugin {
    const LidarscoutCudaRasterApi* api = nullptr;
    void* context = nullptr;
    std::string device, failure;
    std::mutex draw_mutex;  // one frame at a time per context
};

const LidarscoutCudaRasterApi* open_api() {
    std::string tried;
    const PluginEntry p = open_plugin_entry(plugin_candidates(), "lidarscout_cuda_raster_api",
                                            "CUDA rasterizer plugin", tried);
    if (!p.entry) {
        throw Error(std::string(kPluginFileName) + " was not built (no nvcc at build time) or not found; looked in: " +
                    tried);
    }
    using Entry = const LidarscoutCudaRasterApi* (*)();
    const LidarscoutCudaRasterApi* api = reinterpret_cast<Entry>(p.entry)();
    if (!api || api->abi != LIDARSCOUT_CUDA_RASTER_ABI) {
        throw Error(p.path + ": not a CUDA rasterizer plugin of this lidarscout version (interface mismatch)");
    }
    return api;
}

void open_plugin(Plugin& p) {
    try {
        p.api = open_api();
    } catch (const Error& e) {
        p.failure = e.what();
        return;
    }
    char error[512] = "";
    p.context = p.api->open(error, sizeof error);
    if (!p.context) {
        p.failure = error[0] ? error : "the GPU could not be opened";
        return;
    }
    p.device = p.api->device_name(p.context);
}

Plugin& plugin() {
    static Plugin p;
    static std::once_flag once;
    std::call_once(once, [] { open_plugin(p); });
    return p;
}

LsrTransform to_abi(const ScreenTransform& s) {
    LsrTransform t;
    for (int k = 0; k < 4; ++k) t.sx[k] = s.sx[k], t.sy[k] = s.sy[k], t.depth[k] = s.depth[k];
    return t;
}

// The colour tables of one frame, read from the CPU Palette (so both backends share them).
struct ColourTables {
    std::vector<std::uint32_t> intensity, classes;
    LsrColours abi{};
};

ColourTables colour_tables(const Palette& palette) {
    ColourTables t;
    t.classes.resize(256);
    for (int c = 0; c < 256; ++c) t.classes[c] = palette.classification(static_cast<std::uint8_t>(c));
    if (palette.mode() == ColourMode::Intensity) {
        t.intensity.resize(65536);
        for (int v = 0; v < 65536; ++v) t.intensity[v] = palette.intensity(static_cast<std::uint16_t>(v));
    }
    const Palette::ElevationMap heights = palette.elevation_map(0.0);
    t.abi.mode = static_cast<int>(palette.mode());
    t.abi.ramp = heights.lut;
    t.abi.ramp_scale = heights.scale;
    t.abi.heightmap_offset = heights.offset;
    t.abi.intensity = t.intensity.empty() ? nullptr : t.intensity.data();
    t.abi.classes = t.classes.data();
    return t;
}

static_assert(static_cast<int>(ColourMode::Rgb) == LSR_COLOUR_RGB);
static_assert(static_cast<int>(ColourMode::Elevation) == LSR_COLOUR_ELEVATION);
static_assert(static_cast<int>(ColourMode::Intensity) == LSR_COLOUR_INTENSITY);
static_assert(static_cast<int>(ColourMode::Classification) == LSR_COLOUR_CLASSIFICATION);
static_assert(static_cast<int>(PatchTint::None) == LSR_TINT_NONE && static_cast<int>(PatchTint::All) == LSR_TINT_ALL);
static_assert(static_cast<int>(PatchTint::Marked) == LSR_TINT_MARKED);

std::vector<LsrPatch> abi_patches(std::span<const HeightmapPatch> patches) {
    std::vector<LsrPatch> out;
    out.reserve(patches.size());
    for (const HeightmapPatch& p : patches) {
        out.push_back({p.origin_x, p.origin_y, p.texel_m, p.size, p.heights.data(),
                       p.colours.empty() ? nullptr : p.colours.data(), p.cache_key, static_cast<int>(p.tint)});
    }
    return out;
}

LsrHeightmapPass heightmap_pass(const Camera& camera, const HeightmapPassSettings& s,
                                const std::vector<LsrPatch>& patches) {
    LsrHeightmapPass h{};
    h.patches = patches.data();
    h.patch_count = static_cast<std::uint32_t>(patches.size());
    h.screen = to_abi(camera.screen_transform(camera.x, camera.y, camera.z));
    h.camera_x = camera.x, h.camera_y = camera.y, h.camera_z = camera.z;
    h.focal_px = camera.focal_px(), h.near_m = camera.near_m;
    h.depth_scale = 1.0f + s.depth_bias;
    h.lod_quad_px = s.lod_quad_px;
    h.fixed_step = s.fixed_step;
    h.skirt_quads = s.skirt_quads;
    const float length = std::sqrt(s.sun[0] * s.sun[0] + s.sun[1] * s.sun[1] + s.sun[2] * s.sun[2]);
    for (int k = 0; k < 3; ++k) h.sun[k] = length > 0.0f ? s.sun[k] / length : (k == 2 ? 1.0f : 0.0f);
    h.ambient = s.ambient;
    h.level_gain = level_gain(h.sun[2], s.ambient);
    h.fill_outline = s.fill_outline ? 1 : 0;
    for (int k = 0; k < 3; ++k) h.tint_rgb[k] = s.tint_rgb[k];
    h.tint_strength = s.tint_strength;
    return h;
}

// Per layer, its batches with the camera transform for each batch origin.
std::vector<std::vector<LsrBatch>> abi_batches(const Camera& camera, const Palette& palette,
                                               std::span<const PointLayer> layers) {
    std::vector<std::vector<LsrBatch>> out;
    for (const PointLayer& layer : layers) {
        auto& batches = out.emplace_back();
        for (const PointBatch& b : layer.batches) {
            PointPassSettings pass;
            pass.adaptive_size = layer.adaptive_size;
            batches.push_back({reinterpret_cast<const LsrPoint*>(b.points.data()), b.points.size(),
                               to_abi(camera.screen_transform(b.origin_x, b.origin_y, b.origin_z)),
                               palette.elevation_map(b.origin_z).offset, b.cache_key,
                               adaptive_scale(pass, b, camera)});
        }
    }
    return out;
}

}  // namespace

std::vector<std::string> plugin_candidates() {
    return lidarscout::plugin_candidates("LIDARSCOUT_CUDA_RASTER", kPluginFileName, LIDARSCOUT_BUILD_DIR);
}

std::string unavailable_reason() { return plugin().failure; }

std::string device_name() { return plugin().device; }

// The filter as the kernels test it.
LsrPointFilter abi_filter(const PointFilter& filter) {
    LsrPointFilter f{};
    f.active = filter.keeps_everything() ? 0 : 1;
    for (unsigned c = 0; c < 256; ++c) {
        if (filter.keeps_class(static_cast<std::uint8_t>(c))) f.classes[c / 32] |= 1u << (c % 32);
    }
    f.return_kinds = filter.keeps_every_return() ? 0xFFu : filter.return_kinds;
    f.intensity_min = filter.intensity_min, f.intensity_max = filter.intensity_max;
    return f;
}

FrameImage draw_frame(const Camera& camera, std::span<const HeightmapPatch> heightmaps,
                      std::span<const PointLayer> layers, const FrameSettings& settings) {
    Plugin& p = plugin();
    if (!p.context) throw Error("CUDA backend unavailable: " + p.failure);
    const Palette palette(settings.colour);
    const ColourTables colours = colour_tables(palette);
    const std::vector<LsrPatch> patches = abi_patches(heightmaps);
    const auto batches = abi_batches(camera, palette, layers);
    std::vector<LsrPointLayer> abi_layers;
    for (std::size_t l = 0; l < layers.size(); ++l) {
        abi_layers.push_back({batches[l].data(), static_cast<std::uint32_t>(batches[l].size()), layers[l].point_size,
                              kMaxAdaptivePointSize});
    }
    LsrFrame frame{};
    frame.width = camera.width, frame.height = camera.height;
    frame.near_m = static_cast<float>(camera.near_m), frame.far_m = static_cast<float>(camera.far_m);
    frame.colours = colours.abi;
    frame.colours.filter = abi_filter(settings.filter);
    frame.heightmaps = heightmap_pass(camera, settings.heightmaps, patches);
    frame.layers = abi_layers.data();
    frame.layer_count = static_cast<std::uint32_t>(abi_layers.size());
    frame.chunk_points = static_cast<std::uint32_t>(std::clamp<std::size_t>(settings.chunk_points, 1, 1u << 30));
    frame.resolve = {settings.resolve.background, settings.resolve.edl_strength, settings.resolve.edl_radius_px};
    FrameImage out;
    out.image = {camera.width, camera.height, std::vector<std::uint32_t>(static_cast<std::size_t>(camera.width) *
                                                                         camera.height)};
    std::uint64_t drawn = 0;
    char error[512] = "";
    std::lock_guard lock(p.draw_mutex);
    if (p.api->draw(p.context, &frame, out.image.pixels.data(), &drawn, error, sizeof error) != 0) {
        throw Error(std::string("CUDA backend: ") + error);
    }
    out.drawn_pixels = static_cast<std::size_t>(drawn);
    return out;
}

}  // namespace lidarscout::render::cuda
