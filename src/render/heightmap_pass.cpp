// The heightmap pass: per patch, cull, pick a LOD step, build the corner grid, then draw two
// shaded triangles per defined block and the boundary skirts.
#include "render/heightmap_pass.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include "core/error.hpp"
#include "render/triangle_raster.hpp"

namespace lidarscout::render {
namespace {

constexpr float kUntexturedGrey = 170.0f;
constexpr int kMaxPatchSize = 4096;

// Per-frame constants shared by every patch.
struct Frame {
    const Camera* camera;
    ScreenTransform screen;  // camera-relative coordinates -> pixels
    float near_m, far_m, width, height;
    Palette palette;
    std::array<float, 3> sun;
    float ambient, depth_scale;
    const HeightmapPassSettings* settings;
};

struct PatchStats {
    float z_min = std::numeric_limits<float>::infinity(), z_max = -std::numeric_limits<float>::infinity();
    bool all_defined = true;
    bool any_defined() const { return z_min <= z_max; }
};

struct GridVertex {
    float x = 0, y = 0, z = 0;  // camera-relative world position
    RasterVertex screen;
    bool drawable = false;  // height defined and in front of the near plane
};

// Scratch space of one thread, reused from patch to patch.
struct Scratch {
    std::vector<GridVertex> grid;
    std::vector<char> block_drawn;
};

PatchStats patch_stats(const HeightmapPatch& patch) {
    PatchStats s;
    for (const float h : patch.heights) {
        if (std::isnan(h)) {
            s.all_defined = false;
            continue;
        }
        s.z_min = std::min(s.z_min, h);
        s.z_max = std::max(s.z_max, h);
    }
    return s;
}

void check_patch(const HeightmapPatch& patch, std::size_t index) {
    const bool size_ok = patch.size >= 1 && patch.size <= kMaxPatchSize;
    const std::size_t texels = size_ok ? static_cast<std::size_t>(patch.size) * patch.size : 0;
    const bool ok = size_ok && patch.heights.size() == texels &&
                    (patch.colours.empty() || patch.colours.size() == texels) && patch.texel_m > 0 &&
                    std::isfinite(patch.texel_m) && std::isfinite(patch.origin_x) && std::isfinite(patch.origin_y);
    if (!ok) {
        throw Error("heightmap pass: patch " + std::to_string(index) +
                    " needs a size in 1..4096, size x size heights (and colours, or none) and a positive texel size");
    }
}

void check_settings(const Framebuffer& fb, const Camera& camera, const HeightmapPassSettings& s) {
    fb.check_size(camera.width, camera.height, "heightmap pass");
    if (!(s.depth_bias >= 0.0f) || !(s.lod_quad_px > 0.0f) || s.fixed_step < 0 || !(s.skirt_quads >= 0.0f) ||
        !(s.ambient >= 0.0f && s.ambient <= 1.0f)) {
        throw Error("heightmap pass: depth bias, skirt and fixed step must be >= 0, the LOD size > 0 and ambient "
                    "within [0, 1]");
    }
}

std::array<float, 3> normalised(std::array<float, 3> v) {
    const float length = std::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
    if (!(length > 0.0f)) return {0.0f, 0.0f, 1.0f};
    return {v[0] / length, v[1] / length, v[2] / length};
}

Frame make_frame(const Camera& camera, const HeightmapPassSettings& settings) {
    return Frame{&camera,
                 camera.screen_transform(camera.x, camera.y, camera.z),
                 static_cast<float>(camera.near_m),
                 static_cast<float>(camera.far_m),
                 static_cast<float>(camera.width),
                 static_cast<float>(camera.height),
                 Palette(settings.colour),
                 normalised(settings.sun),
                 settings.ambient,
                 1.0f + settings.depth_bias,
                 &settings};
}

float row_dot(const std::array<float, 4>& row, float x, float y, float z) {
    return row[0] * x + row[1] * y + row[2] * z + row[3];
}

// Whether any part of the camera-relative box [lo, hi] can be on screen: it is culled when all
// 8 corners are outside the same frustum plane.
bool box_in_view(const Frame& f, const std::array<float, 3>& lo, const std::array<float, 3>& hi) {
    std::array<int, 6> outside{};
    for (int corner = 0; corner < 8; ++corner) {
        const float x = (corner & 1) ? hi[0] : lo[0], y = (corner & 2) ? hi[1] : lo[1];
        const float z = (corner & 4) ? hi[2] : lo[2];
        const float sx = row_dot(f.screen.sx, x, y, z), sy = row_dot(f.screen.sy, x, y, z);
        const float w = row_dot(f.screen.depth, x, y, z);
        const std::array<float, 6> planes = {sx, f.width * w - sx, sy, f.height * w - sy, w - f.near_m, f.far_m - w};
        for (int p = 0; p < 6; ++p) outside[p] += planes[p] < 0.0f;
    }
    return std::none_of(outside.begin(), outside.end(), [](int n) { return n == 8; });
}

// Corner k of a grid at `step` (the last corner is always the patch edge).
int corner_at(int k, int step, int size) { return std::min(k * step, size); }
int corner_count(int step, int size) { return (size + step - 1) / step + 1; }

float texel_height(const HeightmapPatch& patch, int i, int j) {
    return patch.heights[static_cast<std::size_t>(j) * patch.size + i];
}

bool on_boundary(const HeightmapPatch& patch, int ci, int cj) {
    return ci == 0 || cj == 0 || ci == patch.size || cj == patch.size;
}

// A boundary corner's height extrapolated linearly (bilinearly) from the nearest 2 x 2 texel
// centres, so that both patches of a seam arrive at nearly the same edge height (they differ
// by the terrain's curvature, not its slope); `fallback` where a texel is NaN or the patch
// is 1 texel wide.
float extrapolated_height(const HeightmapPatch& patch, int ci, int cj, float fallback) {
    if (patch.size < 2) return fallback;
    // Corner ci sits at texel-centre coordinate ci - 0.5.
    const int i0 = std::clamp(ci - 1, 0, patch.size - 2), j0 = std::clamp(cj - 1, 0, patch.size - 2);
    const float u = (ci - 0.5f) - i0, v = (cj - 0.5f) - j0;
    const float h00 = texel_height(patch, i0, j0), h10 = texel_height(patch, i0 + 1, j0);
    const float h01 = texel_height(patch, i0, j0 + 1), h11 = texel_height(patch, i0 + 1, j0 + 1);
    const float h = (1 - v) * ((1 - u) * h00 + u * h10) + v * ((1 - u) * h01 + u * h11);
    return std::isnan(h) ? fallback : h;
}

// Mean height and colour of the defined texels around corner (ci, cj) (the height
// extrapolated on the patch boundary); false if none is defined.
bool corner_attributes(const HeightmapPatch& patch, int ci, int cj, float& height, std::array<float, 3>& rgb) {
    float sum_h = 0.0f;
    std::array<float, 3> sum_c{};
    int n = 0;
    for (int j = std::max(cj - 1, 0); j <= std::min(cj, patch.size - 1); ++j) {
        for (int i = std::max(ci - 1, 0); i <= std::min(ci, patch.size - 1); ++i) {
            const std::size_t t = static_cast<std::size_t>(j) * patch.size + i;
            if (std::isnan(patch.heights[t])) continue;
            sum_h += patch.heights[t];
            if (!patch.colours.empty()) {
                const std::uint32_t c = patch.colours[t];
                sum_c[0] += red(c), sum_c[1] += green(c), sum_c[2] += blue(c);
            }
            ++n;
        }
    }
    if (n == 0) return false;
    height = on_boundary(patch, ci, cj) ? extrapolated_height(patch, ci, cj, sum_h / n) : sum_h / n;
    rgb = patch.colours.empty() ? std::array<float, 3>{kUntexturedGrey, kUntexturedGrey, kUntexturedGrey}
                                : std::array<float, 3>{sum_c[0] / n, sum_c[1] / n, sum_c[2] / n};
    return true;
}

void set_colour(RasterVertex& v, std::uint32_t rgba) { v.r = red(rgba), v.g = green(rgba), v.b = blue(rgba); }

RasterVertex project(const Frame& f, float x, float y, float z) {
    RasterVertex v;
    v.depth = row_dot(f.screen.depth, x, y, z);
    const float inv = 1.0f / v.depth;
    v.x = row_dot(f.screen.sx, x, y, z) * inv;
    v.y = row_dot(f.screen.sy, x, y, z) * inv;
    return v;
}

// Camera-relative positions of the corner columns (x) or rows (y), from the origin in double.
float corner_offset(double origin, double camera, int corner, double texel_m) {
    return static_cast<float>((origin - camera) + corner * texel_m);
}

void build_grid(const Frame& f, const HeightmapPatch& patch, int step, std::vector<GridVertex>& grid) {
    const int n = corner_count(step, patch.size);
    grid.assign(static_cast<std::size_t>(n) * n, GridVertex{});
    const auto elevation = f.palette.elevation_map(0.0);
    const bool by_height = f.palette.mode() == ColourMode::Elevation;
    for (int kj = 0; kj < n; ++kj) {
        const int cj = corner_at(kj, step, patch.size);
        const float y = corner_offset(patch.origin_y, f.camera->y, cj, patch.texel_m);
        for (int ki = 0; ki < n; ++ki) {
            const int ci = corner_at(ki, step, patch.size);
            GridVertex& v = grid[static_cast<std::size_t>(kj) * n + ki];
            float height = 0.0f;
            std::array<float, 3> rgb{};
            if (!corner_attributes(patch, ci, cj, height, rgb)) continue;
            v.x = corner_offset(patch.origin_x, f.camera->x, ci, patch.texel_m);
            v.y = y;
            v.z = static_cast<float>(static_cast<double>(height) - f.camera->z);
            v.screen = project(f, v.x, v.y, v.z);
            v.drawable = v.screen.depth >= f.near_m;
            if (by_height) {
                set_colour(v.screen, elevation(height));
            } else {
                v.screen.r = rgb[0], v.screen.g = rgb[1], v.screen.b = rgb[2];
            }
        }
    }
}

bool texels_defined(const HeightmapPatch& patch, int i0, int i1, int j0, int j1) {
    for (int j = j0; j < j1; ++j) {
        for (int i = i0; i < i1; ++i) {
            if (std::isnan(patch.heights[static_cast<std::size_t>(j) * patch.size + i])) return false;
        }
    }
    return true;
}

// Which blocks (step x step texels) are drawn: those whose texels are all defined.
void mark_blocks(const HeightmapPatch& patch, int step, bool all_defined, std::vector<char>& drawn) {
    const int n = corner_count(step, patch.size) - 1;
    drawn.assign(static_cast<std::size_t>(n) * n, 1);
    if (all_defined) return;
    for (int bj = 0; bj < n; ++bj) {
        for (int bi = 0; bi < n; ++bi) {
            drawn[static_cast<std::size_t>(bj) * n + bi] =
                texels_defined(patch, corner_at(bi, step, patch.size), corner_at(bi + 1, step, patch.size),
                               corner_at(bj, step, patch.size), corner_at(bj + 1, step, patch.size));
        }
    }
}

// Lambert shading of a face: ambient + (1 - ambient) * max(0, n . sun), n facing up.
float face_shade(const Frame& f, const GridVertex& a, const GridVertex& b, const GridVertex& c) {
    const float ux = b.x - a.x, uy = b.y - a.y, uz = b.z - a.z;
    const float vx = c.x - a.x, vy = c.y - a.y, vz = c.z - a.z;
    std::array<float, 3> n = normalised({uy * vz - uz * vy, uz * vx - ux * vz, ux * vy - uy * vx});
    if (n[2] < 0.0f) n = {-n[0], -n[1], -n[2]};
    const float lambert = std::max(0.0f, n[0] * f.sun[0] + n[1] * f.sun[1] + n[2] * f.sun[2]);
    return f.ambient + (1.0f - f.ambient) * lambert;
}

void draw_face(Framebuffer& fb, const Frame& f, const GridVertex& a, const GridVertex& b, const GridVertex& c) {
    if (!(a.drawable && b.drawable && c.drawable)) return;
    draw_triangle(fb, a.screen, b.screen, c.screen, face_shade(f, a, b, c), f.depth_scale);
}

// A vertical strip hanging `depth` metres down from the boundary edge a-b, shaded like the
// surface triangle (a, b, inner) it continues, so that where it shows through a slit it looks
// like the surface.
void draw_skirt(Framebuffer& fb, const Frame& f, const GridVertex& a, const GridVertex& b, const GridVertex& inner,
                float depth) {
    if (!(a.drawable && b.drawable && inner.drawable)) return;
    GridVertex a_low = a, b_low = b;
    for (GridVertex* v : {&a_low, &b_low}) {
        v->z -= depth;
        const RasterVertex colour = v->screen;
        v->screen = project(f, v->x, v->y, v->z);
        v->screen.r = colour.r, v->screen.g = colour.g, v->screen.b = colour.b;
        v->drawable = v->screen.depth >= f.near_m;
    }
    if (!(a_low.drawable && b_low.drawable)) return;
    const float shade = face_shade(f, a, b, inner);
    draw_triangle(fb, a.screen, b.screen, b_low.screen, shade, f.depth_scale);
    draw_triangle(fb, a.screen, b_low.screen, a_low.screen, shade, f.depth_scale);
}

// Corner (ki, kj) of a grid of n x n blocks.
const GridVertex& grid_at(const Scratch& s, int n, int ki, int kj) {
    return s.grid[static_cast<std::size_t>(kj) * (n + 1) + ki];
}

// Skirts along the four patch edges, under every drawn boundary block.
void draw_skirts(Framebuffer& fb, const Frame& f, const Scratch& s, int n, float depth) {
    const auto vertex = [&](int ki, int kj) -> const GridVertex& { return grid_at(s, n, ki, kj); };
    const auto drawn = [&](int bi, int bj) { return s.block_drawn[static_cast<std::size_t>(bj) * n + bi] != 0; };
    for (int k = 0; k < n; ++k) {
        if (drawn(k, 0)) draw_skirt(fb, f, vertex(k, 0), vertex(k + 1, 0), vertex(k + 1, 1), depth);  // south
        if (drawn(k, n - 1)) draw_skirt(fb, f, vertex(k, n), vertex(k + 1, n), vertex(k, n - 1), depth);  // north
        if (drawn(0, k)) draw_skirt(fb, f, vertex(0, k), vertex(0, k + 1), vertex(1, k + 1), depth);  // west
        if (drawn(n - 1, k)) draw_skirt(fb, f, vertex(n, k), vertex(n, k + 1), vertex(n - 1, k), depth);  // east
    }
}

void draw_blocks(Framebuffer& fb, const Frame& f, const Scratch& s, int n) {
    const auto vertex = [&](int ki, int kj) -> const GridVertex& { return grid_at(s, n, ki, kj); };
    for (int bj = 0; bj < n; ++bj) {
        for (int bi = 0; bi < n; ++bi) {
            if (!s.block_drawn[static_cast<std::size_t>(bj) * n + bi]) continue;
            const GridVertex &v00 = vertex(bi, bj), &v10 = vertex(bi + 1, bj);
            const GridVertex &v01 = vertex(bi, bj + 1), &v11 = vertex(bi + 1, bj + 1);
            draw_face(fb, f, v00, v10, v11);
            draw_face(fb, f, v00, v11, v01);
        }
    }
}

bool patch_in_view(const Frame& f, const HeightmapPatch& patch, const PatchStats& stats) {
    const double side = patch.size * patch.texel_m;
    const Camera& c = *f.camera;
    const auto offset = [](double value, double camera) { return static_cast<float>(value - camera); };
    const std::array<float, 3> lo = {offset(patch.origin_x, c.x), offset(patch.origin_y, c.y),
                                     offset(stats.z_min, c.z)};
    const std::array<float, 3> hi = {offset(patch.origin_x + side, c.x), offset(patch.origin_y + side, c.y),
                                     offset(stats.z_max, c.z)};
    return box_in_view(f, lo, hi);
}

void draw_patch(Framebuffer& fb, const Frame& f, const HeightmapPatch& patch, Scratch& scratch) {
    const PatchStats stats = patch_stats(patch);
    if (!stats.any_defined() || !patch_in_view(f, patch, stats)) return;
    const HeightmapPassSettings& settings = *f.settings;
    const int step = settings.fixed_step > 0
                         ? std::min(settings.fixed_step, patch.size)
                         : lod_step(patch, stats.z_min, stats.z_max, *f.camera, settings.lod_quad_px);
    build_grid(f, patch, step, scratch.grid);
    mark_blocks(patch, step, stats.all_defined, scratch.block_drawn);
    const int blocks = corner_count(step, patch.size) - 1;
    draw_blocks(fb, f, scratch, blocks);
    if (settings.skirt_quads > 0.0f) {
        draw_skirts(fb, f, scratch, blocks, static_cast<float>(settings.skirt_quads * step * patch.texel_m));
    }
}

}  // namespace

int lod_step(const HeightmapPatch& patch, double z_min, double z_max, const Camera& camera, float lod_quad_px) {
    const double side = patch.size * patch.texel_m;
    const auto gap = [](double lo, double hi, double p) { return std::max({lo - p, 0.0, p - hi}); };
    const double distance =
        std::hypot(gap(patch.origin_x, patch.origin_x + side, camera.x),
                   gap(patch.origin_y, patch.origin_y + side, camera.y), gap(z_min, z_max, camera.z));
    const double texel_px = patch.texel_m * camera.focal_px() / std::max(distance, camera.near_m);
    int step = 1;
    while (step * 2 <= patch.size && texel_px * step * 2 <= lod_quad_px) step *= 2;
    return step;
}

void draw_heightmaps(Framebuffer& fb, const Camera& camera, std::span<const HeightmapPatch> patches,
                     const HeightmapPassSettings& settings, ThreadPool& pool) {
    check_settings(fb, camera, settings);
    for (std::size_t i = 0; i < patches.size(); ++i) check_patch(patches[i], i);
    const Frame frame = make_frame(camera, settings);
    // Patches go to the pool in runs, each run with its own scratch buffers. (A thread_local
    // scratch registered its destructor on first use through __cxa_thread_atexit, which takes
    // the dynamic loader's lock: a frame drawn while LibTorch was being loaded stalled 0.7 s.)
    const std::size_t runs = std::min<std::size_t>(patches.size(), std::size_t{pool.size()} * 8);
    pool.for_each(runs, [&](std::size_t r) {
        Scratch scratch;
        for (std::size_t i = r * patches.size() / runs; i < (r + 1) * patches.size() / runs; ++i) {
            draw_patch(fb, frame, patches[i], scratch);
        }
    });
}

}  // namespace lidarscout::render
