// The CPU-versus-CUDA cases of gpu_cases.hpp: their scenes, controls and comparisons.
#include "render/gpu_cases.hpp"

#include <array>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>

#include "core/error.hpp"
#include "core/point_filter.hpp"
#include "render/framebuffer.hpp"
#include "render/image_compare.hpp"

namespace lidarscout::render::gpu_cases {
namespace {

constexpr double kOx = 600'000.0, kOy = 4'200'000.0;
constexpr int kSize = 64;
constexpr int kPointColumns = 300;
constexpr double kColumnM = 4.0, kRowM = 6.0;  // the points' grid

float terrain(double x, double y) { return static_cast<float>(120.0 + 15.0 * std::sin(x / 90.0) * std::cos(y / 70.0)); }

// A 2 x 2 block of 640 m patches; patch 1 is untextured, patch 3 has a hole.
void add_patches(Scene& s) {
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

// 60,000 points on a 4 x 6 m grid above the patches, a third in the chunk layer, the rest in the
// full-resolution one; return kinds of 3-return pulses (every tenth unknown), classes 0-24.
void add_points(Scene& s) {
    for (int k = 0; k < 60'000; ++k) {
        const double x = (k % kPointColumns) * kColumnM, y = (k / kPointColumns) * kRowM;
        PointAttr p;
        p.dx = static_cast<float>(x), p.dy = static_cast<float>(y);
        p.dz = terrain(kOx + 40.0 + x, kOy + 40.0 + y) + 2.0f + (k % 7) - 100.0f;
        p.r = static_cast<std::uint8_t>(k), p.g = static_cast<std::uint8_t>(k >> 3), p.b = 200;
        p.intensity = static_cast<std::uint16_t>(k * 13), p.classification = static_cast<std::uint8_t>(k % 25);
        p.returns = k % 10 == 0 ? 0 : returns::kinds_of(static_cast<std::uint8_t>(1 + k % 3), 3);
        (k % 3 ? s.points_a : s.points_b).push_back(p);
    }
    s.chunk.push_back({kOx + 40.0, kOy + 40.0, 100.0, s.points_b});
    s.full.push_back({kOx + 40.0, kOy + 40.0, 100.0, s.points_a});
    // The spacing of each layer's points on the ground (one point per this many square metres).
    s.chunk.back().spacing_m = static_cast<float>(std::sqrt(kColumnM * kRowM * 3.0));
    s.full.back().spacing_m = static_cast<float>(std::sqrt(kColumnM * kRowM * 1.5));
}

// Close over the patches, looking north-east and down: near triangles are large on screen.
Camera test_camera() {
    Camera c;
    c.x = kOx + 300.0, c.y = kOy + 200.0, c.z = 180.0;
    c.yaw_deg = 30, c.pitch_deg = -25, c.width = 640, c.height = 400, c.near_m = 1.0, c.far_m = 5000.0;
    return c;
}

void patches_only(Scene& s) {
    add_patches(s);
    s.camera = test_camera();
}

// Patches and both point layers (chunk points of 3 pixels, full-resolution ones of 1).
void full_scene(Scene& s, ColourMode mode) {
    patches_only(s);
    add_points(s);
    s.layers = {{s.chunk, 3}, {s.full, 1}};
    s.settings.colour.mode = mode;
    s.settings.colour.z_min = 90, s.settings.colour.z_max = 160;
    s.settings.chunk_points = 5'000;
}

void filtered(Scene& s, std::string_view classes, std::string_view kinds, std::string_view intensity) {
    full_scene(s, ColourMode::Rgb);
    s.settings.filter = PointFilter::parse(classes, kinds, intensity);
}

void rgb_edl(Scene& s) {
    full_scene(s, ColourMode::Rgb);
    s.settings.resolve.edl_strength = 1.0f;
}
void elevation(Scene& s) { full_scene(s, ColourMode::Elevation); }
void intensity(Scene& s) { full_scene(s, ColourMode::Intensity); }
void classification(Scene& s) { full_scene(s, ColourMode::Classification); }
void filter_classes(Scene& s) { filtered(s, "2-6", "", ""); }
void filter_returns(Scene& s) { filtered(s, "", "last", ""); }
void filter_intensity(Scene& s) { filtered(s, "", "", "20000-45000"); }
void filter_combined(Scene& s) { filtered(s, "2,9,12-20", "first,single", "-50000"); }

// Patch 0 tinted whole, patch 2 where its left half is marked (colour alpha below 255).
void tint(Scene& s) {
    patches_only(s);
    for (int j = 0; j < kSize; ++j) {
        for (int i = 0; i < kSize / 2; ++i) {
            std::uint32_t& c = s.colours[2][static_cast<std::size_t>(j) * kSize + i];
            c = (c & 0x00FFFFFFu) | (128u << 24);
        }
    }
    s.patches[0].tint = PatchTint::All;
    s.patches[2].tint = PatchTint::Marked;
}

void adaptive(Scene& s) {
    full_scene(s, ColourMode::Rgb);
    for (PointLayer& layer : s.layers) layer.adaptive_size = true;
}

void heightmaps(Scene& s) { patches_only(s); }
void heightmaps_full_detail(Scene& s) {
    patches_only(s);
    s.settings.colour.mode = ColourMode::Elevation;
    s.settings.colour.z_min = 90, s.settings.colour.z_max = 160;
    s.settings.heightmaps.fixed_step = 1;
    s.settings.heightmaps.fill_outline = false;
    s.settings.heightmaps.skirt_quads = 0.0f;
}
void kept(Scene& s) { full_scene(s, ColourMode::Rgb); }

// The controls.
void no_edl(Scene& s) { s.settings.resolve.edl_strength = 0.0f; }
void rgb_colours(Scene& s) { s.settings.colour.mode = ColourMode::Rgb; }
void no_filter(Scene& s) { s.settings.filter = PointFilter(); }
void no_tint(Scene& s) {
    for (HeightmapPatch& p : s.patches) p.tint = PatchTint::None;
}
void fixed_sizes(Scene& s) {
    for (PointLayer& layer : s.layers) layer.adaptive_size = false;
}
void no_patches(Scene& s) { s.patches.clear(); }

constexpr std::array<Case, 13> kCases = {{
    {"rgb_edl", "RGB colours with eye-dome lighting (control: no EDL)", rgb_edl, no_edl},
    {"elevation", "elevation colours (control: RGB)", elevation, rgb_colours},
    {"intensity", "intensity colours (control: RGB)", intensity, rgb_colours},
    {"classification", "class colours (control: RGB)", classification, rgb_colours},
    {"filter_classes", "point filter, classes 2-6 (control: no filter)", filter_classes, no_filter},
    {"filter_returns", "point filter, last returns; unknown kinds kept (control: no filter)", filter_returns,
     no_filter},
    {"filter_intensity", "point filter, intensity 20000-45000 (control: no filter)", filter_intensity, no_filter},
    {"filter_combined", "point filter, classes, first/single returns and intensity (control: no filter)",
     filter_combined, no_filter},
    {"tint", "bare-earth tint, a patch whole and one where marked (control: no tint)", tint, no_tint},
    {"adaptive_spacing", "adaptive point sizes, spacing 8.5 and 6 m (control: fixed sizes)", adaptive,
     fixed_sizes},
    {"heightmaps", "heightmap pass alone, LOD, skirts, outline fill (control: no patches)", heightmaps, no_patches},
    {"heightmaps_full_detail", "heightmap pass at step 1, elevation colours (control: no patches)",
     heightmaps_full_detail, no_patches},
    {"kept_on_gpu", "points and patches kept on the GPU: 3 more frames equal the first (no control)", kept, nullptr,
     3},
}};

// The case's scene, with keys on its batches and patches when it keeps them on the GPU.
void build(const Case& c, Scene& s) {
    c.build(s);
    if (c.kept_frames == 0) return;
    for (PointBatch& b : s.chunk) b.cache_key = new_cache_key();
    for (PointBatch& b : s.full) b.cache_key = new_cache_key();
    for (HeightmapPatch& p : s.patches) p.cache_key = new_cache_key();
}

FrameImage draw(Backend backend, const Scene& s, ThreadPool& pool) {
    return draw_frame(backend, s.camera, s.patches, s.layers, s.settings, pool);
}

std::string percent(double share) {
    char text[32];
    std::snprintf(text, sizeof text, "%.2f%%", 100.0 * share);
    return text;
}

void add_failure(std::string& failures, const std::string& failure) {
    failures += (failures.empty() ? "" : "; ") + failure;
}

}  // namespace

std::span<const Case> cases() { return kCases; }

const Case& find_case(std::string_view name) {
    std::string known;
    for (const Case& c : kCases) {
        if (c.name == name) return c;
        known += (known.empty() ? "" : ", ") + std::string(c.name);
    }
    throw Error("unknown case '" + std::string(name) + "' (known: " + known + ")");
}

double share_close(const RgbaImage& a, const RgbaImage& b, int levels) {
    if (a.pixels.size() != b.pixels.size() || a.pixels.empty()) return 0.0;
    std::size_t close = 0;
    for (std::size_t i = 0; i < a.pixels.size(); ++i) {
        const std::uint32_t p = a.pixels[i], q = b.pixels[i];
        const auto near = [levels](int x, int y) { return std::abs(x - y) <= levels; };
        close += near(red(p), red(q)) && near(green(p), green(q)) && near(blue(p), blue(q));
    }
    return static_cast<double>(close) / a.pixels.size();
}

CpuSide draw_on_cpu(const Case& c, ThreadPool& pool) {
    CpuSide out;
    Scene scene;
    build(c, scene);
    out.frame = draw(Backend::Cpu, scene, pool);
    out.drawn_share = static_cast<double>(out.frame.drawn_pixels) / out.frame.image.pixels.size();
    if (out.drawn_share < 0.5) {
        add_failure(out.failure, "draws " + percent(out.drawn_share) + " of the pixels, not half");
    }
    if (!c.control) return out;
    Scene control;
    build(c, control);
    c.control(control);
    out.control_changed_share = 1.0 - share_close(out.frame.image, draw(Backend::Cpu, control, pool).image);
    if (out.control_changed_share < kMinControlChangedShare) {
        add_failure(out.failure, "differs from its control in " + percent(out.control_changed_share) +
                                     " of the pixels, less than " + percent(kMinControlChangedShare));
    }
    return out;
}

GpuSide draw_on_gpu(const Case& c, const CpuSide& cpu, ThreadPool& pool) {
    GpuSide out;
    Scene scene;
    build(c, scene);
    const FrameImage gpu = draw(Backend::Cuda, scene, pool);
    out.image = gpu.image;
    // draw_frame draws on the CPU when the GPU fails during a frame: that image proves nothing.
    if (const std::string reason = cuda_unavailable_reason(); !reason.empty()) {
        out.failure = "the GPU failed (" + reason + ")";
        return out;
    }
    const std::size_t pixels = cpu.frame.image.pixels.size();
    if (gpu.image.width != cpu.frame.image.width || gpu.image.pixels.size() != pixels) {
        out.failure = "the GPU's image has another size";
        return out;
    }
    out.close_share = share_close(cpu.frame.image, gpu.image);
    out.psnr_db = image_psnr_db(gpu.image, cpu.frame.image);
    out.drawn_pixels = gpu.drawn_pixels;
    if (out.close_share < kMinCloseShare) {
        add_failure(out.failure, percent(out.close_share) + " of the pixels within " +
                                     std::to_string(kMaxLevelDifference) + " levels, less than " +
                                     percent(kMinCloseShare));
    }
    const double drawn_difference =
        std::abs(static_cast<double>(gpu.drawn_pixels) - static_cast<double>(cpu.frame.drawn_pixels)) / pixels;
    if (drawn_difference > kMaxDrawnDifferenceShare) {
        add_failure(out.failure, "drawn pixels " + std::to_string(gpu.drawn_pixels) + " against the CPU's " +
                                     std::to_string(cpu.frame.drawn_pixels));
    }
    for (int frame = 0; frame < c.kept_frames; ++frame) {
        out.kept_frames_equal += draw(Backend::Cuda, scene, pool).image.pixels == gpu.image.pixels;
    }
    if (out.kept_frames_equal < c.kept_frames) {
        add_failure(out.failure, std::to_string(c.kept_frames - out.kept_frames_equal) + " of " +
                                     std::to_string(c.kept_frames) + " frames from kept data differ from the first");
    }
    return out;
}

void write_ppm(const std::string& path, const RgbaImage& image) {
    const std::string part = path + ".part";
    std::ofstream out(part, std::ios::binary);
    out << "P6\n" << image.width << ' ' << image.height << "\n255\n";
    for (const std::uint32_t p : image.pixels) {
        const char rgb[3] = {static_cast<char>(red(p)), static_cast<char>(green(p)), static_cast<char>(blue(p))};
        out.write(rgb, 3);
    }
    out.close();
    if (!out) throw Error(part + ": could not be written");
    std::filesystem::rename(part, path);
}

}  // namespace lidarscout::render::gpu_cases
