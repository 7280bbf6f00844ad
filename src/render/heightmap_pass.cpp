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
    float level_gain;  // 1 / the light level ground gets: level ground shows its texture's colour
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

// Scratch space of one thread, reused from patch to patch: the patch's corners, computed when a
// block first needs them, and where texels are undefined, a summed-area table of them.
struct Scratch {
    std::vector<GridVertex> corners;   // (size + 1)^2 when memoised
    std::vector<std::uint32_t> stamp;  // corners[k] belongs to this patch when stamp[k] == generation
    std::uint32_t generation = 0;
    std::vector<int> undefined;        // (size + 1)^2: undefined texels below and left of each corner
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
                    (patch.colours.empty() || patch.colours.size() == texels) &&
                    (patch.tint != PatchTint::Marked || !patch.colours.empty()) && patch.texel_m > 0 &&
                    std::isfinite(patch.texel_m) && std::isfinite(patch.origin_x) && std::isfinite(patch.origin_y);
    if (!ok) {
        throw Error("heightmap pass: patch " + std::to_string(index) +
                    " needs a size in 1..4096, size x size heights (and colours, or none; a marked tint needs "
                    "them) and a positive texel size");
    }
}

void check_settings(const Framebuffer& fb, const Camera& camera, const HeightmapPassSettings& s) {
    fb.check_size(camera.width, camera.height, "heightmap pass");
    if (!(s.depth_bias >= 0.0f) || !(s.lod_quad_px > 0.0f) || s.fixed_step < 0 || !(s.skirt_quads >= 0.0f) ||
        !(s.ambient >= 0.0f && s.ambient <= 1.0f) || !(s.tint_strength >= 0.0f && s.tint_strength <= 1.0f)) {
        throw Error("heightmap pass: depth bias, skirt and fixed step must be >= 0, the LOD size > 0, ambient "
                    "and the tint's strength within [0, 1]");
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
                 &settings,
                 level_gain(normalised(settings.sun)[2], settings.ambient)};
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

// Whether texel t of the patch is drawn tinted (PatchTint).
bool texel_tinted(const HeightmapPatch& patch, std::size_t t) {
    return patch.tint == PatchTint::All || (patch.tint == PatchTint::Marked && alpha(patch.colours[t]) < 255);
}

// What a corner takes from the defined texels around it: their mean height and colour and the
// share of them drawn tinted.
struct CornerAttributes {
    float height = 0.0f;
    std::array<float, 3> rgb{};
    float tinted = 0.0f;
};

// Mean height and colour of the defined texels around corner (ci, cj) (the height
// extrapolated on the patch boundary); false if none is defined.
bool corner_attributes(const HeightmapPatch& patch, int ci, int cj, CornerAttributes& out) {
    float sum_h = 0.0f;
    std::array<float, 3> sum_c{};
    int n = 0, tinted = 0;
    for (int j = std::max(cj - 1, 0); j <= std::min(cj, patch.size - 1); ++j) {
        for (int i = std::max(ci - 1, 0); i <= std::min(ci, patch.size - 1); ++i) {
            const std::size_t t = static_cast<std::size_t>(j) * patch.size + i;
            if (std::isnan(patch.heights[t])) continue;
            sum_h += patch.heights[t];
            if (!patch.colours.empty()) {
                const std::uint32_t c = patch.colours[t];
                sum_c[0] += red(c), sum_c[1] += green(c), sum_c[2] += blue(c);
            }
            tinted += texel_tinted(patch, t);
            ++n;
        }
    }
    if (n == 0) return false;
    out.height = on_boundary(patch, ci, cj) ? extrapolated_height(patch, ci, cj, sum_h / n) : sum_h / n;
    out.rgb = patch.colours.empty() ? std::array<float, 3>{kUntexturedGrey, kUntexturedGrey, kUntexturedGrey}
                                    : std::array<float, 3>{sum_c[0] / n, sum_c[1] / n, sum_c[2] / n};
    out.tinted = static_cast<float>(tinted) / n;
    return true;
}

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

// Corner (ci, cj) of `patch`: camera-relative position, projection and colour; not drawable when
// no texel around it is defined or it lies behind the near plane.
GridVertex make_corner(const Frame& f, const HeightmapPatch& patch, int ci, int cj) {
    GridVertex v;
    CornerAttributes a;
    if (!corner_attributes(patch, ci, cj, a)) return v;
    v.x = corner_offset(patch.origin_x, f.camera->x, ci, patch.texel_m);
    v.y = corner_offset(patch.origin_y, f.camera->y, cj, patch.texel_m);
    v.z = static_cast<float>(static_cast<double>(a.height) - f.camera->z);
    v.screen = project(f, v.x, v.y, v.z);
    v.drawable = v.screen.depth >= f.near_m;
    if (f.palette.mode() == ColourMode::Elevation) {
        const std::uint32_t e = f.palette.elevation_map(0.0)(a.height);
        a.rgb = {static_cast<float>(red(e)), static_cast<float>(green(e)), static_cast<float>(blue(e))};
    }
    const float mix = a.tinted * f.settings->tint_strength;
    for (int k = 0; k < 3; ++k) a.rgb[k] += (f.settings->tint_rgb[k] - a.rgb[k]) * mix;
    v.screen.r = a.rgb[0], v.screen.g = a.rgb[1], v.screen.b = a.rgb[2];
    return v;
}

// Lambert shading of a face: ambient + (1 - ambient) * max(0, n . sun), n facing up, scaled so
// that level ground gets 1 (slopes towards the sun are brighter, away from it darker).
float face_shade(const Frame& f, const GridVertex& a, const GridVertex& b, const GridVertex& c) {
    const float ux = b.x - a.x, uy = b.y - a.y, uz = b.z - a.z;
    const float vx = c.x - a.x, vy = c.y - a.y, vz = c.z - a.z;
    std::array<float, 3> n = normalised({uy * vz - uz * vy, uz * vx - ux * vz, ux * vy - uy * vx});
    if (n[2] < 0.0f) n = {-n[0], -n[1], -n[2]};
    const float lambert = std::max(0.0f, n[0] * f.sun[0] + n[1] * f.sun[1] + n[2] * f.sun[2]);
    return (f.ambient + (1.0f - f.ambient) * lambert) * f.level_gain;
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

constexpr int kMaxMemoisedSize = 512;  // larger patches compute their corners each time they are used

// One patch being drawn: its corners on demand, and its undefined texels counted per block.
class PatchDraw {
public:
    PatchDraw(Framebuffer& fb, const Frame& f, const HeightmapPatch& patch, bool all_defined, Scratch& scratch)
        : fb_(fb), f_(f), patch_(patch), all_defined_(all_defined), s_(scratch), n_(patch.size + 1) {
        if (patch.size <= kMaxMemoisedSize) start_memo();
        if (!all_defined) count_undefined();
    }

    // The block of texels [i0, i1) x [j0, j1): drawn whole when all its texels are defined, skipped
    // when none is, else split in four (halves) until blocks of `min_side` texels, drawn when at least
    // half their texels are defined (where their corners are: a corner needs a defined texel beside it).
    void draw_block(int i0, int i1, int j0, int j1, int min_side) {
        const int undefined = undefined_in(i0, i1, j0, j1), texels = (i1 - i0) * (j1 - j0);
        if (undefined == 0) return draw_quad(i0, i1, j0, j1);
        if (undefined == texels) return;
        if (i1 - i0 <= min_side && j1 - j0 <= min_side) {
            if (2 * undefined <= texels) draw_quad(i0, i1, j0, j1);
            return;
        }
        const int im = i1 - i0 > 1 ? (i0 + i1) / 2 : i1, jm = j1 - j0 > 1 ? (j0 + j1) / 2 : j1;
        draw_block(i0, im, j0, jm, min_side);
        if (im < i1) draw_block(im, i1, j0, jm, min_side);
        if (jm < j1) draw_block(i0, im, jm, j1, min_side);
        if (im < i1 && jm < j1) draw_block(im, i1, jm, j1, min_side);
    }

private:
    void start_memo() {
        const std::size_t corners = static_cast<std::size_t>(n_) * n_;
        if (s_.corners.size() < corners) s_.corners.resize(corners), s_.stamp.assign(corners, 0);
        if (++s_.generation == 0) std::fill(s_.stamp.begin(), s_.stamp.end(), 0), s_.generation = 1;
        memo_ = true;
    }

    void count_undefined() {
        s_.undefined.assign(static_cast<std::size_t>(n_) * n_, 0);
        for (int j = 0; j < patch_.size; ++j) {
            int row = 0;
            for (int i = 0; i < patch_.size; ++i) {
                row += std::isnan(texel_height(patch_, i, j));
                s_.undefined[index(i + 1, j + 1)] = s_.undefined[index(i + 1, j)] + row;
            }
        }
    }

    int undefined_in(int i0, int i1, int j0, int j1) const {
        if (all_defined_) return 0;
        const auto& u = s_.undefined;
        return u[index(i1, j1)] - u[index(i0, j1)] - u[index(i1, j0)] + u[index(i0, j0)];
    }

    std::size_t index(int ci, int cj) const { return static_cast<std::size_t>(cj) * n_ + ci; }

    const GridVertex& corner(int ci, int cj) {
        if (!memo_) return scratch_vertex_ = make_corner(f_, patch_, ci, cj);
        const std::size_t k = index(ci, cj);
        if (s_.stamp[k] != s_.generation) s_.corners[k] = make_corner(f_, patch_, ci, cj), s_.stamp[k] = s_.generation;
        return s_.corners[k];
    }

    // Two shaded triangles over texels [i0, i1) x [j0, j1), and skirts under the edges on the patch boundary.
    void draw_quad(int i0, int i1, int j0, int j1) {
        const GridVertex v00 = corner(i0, j0), v10 = corner(i1, j0), v01 = corner(i0, j1), v11 = corner(i1, j1);
        draw_face(fb_, f_, v00, v10, v11);
        draw_face(fb_, f_, v00, v11, v01);
        const float depth = static_cast<float>(f_.settings->skirt_quads * std::max(i1 - i0, j1 - j0) * patch_.texel_m);
        if (!(depth > 0.0f)) return;
        if (j0 == 0) draw_skirt(fb_, f_, v00, v10, v11, depth);                // south
        if (j1 == patch_.size) draw_skirt(fb_, f_, v01, v11, v00, depth);      // north
        if (i0 == 0) draw_skirt(fb_, f_, v00, v01, v11, depth);                // west
        if (i1 == patch_.size) draw_skirt(fb_, f_, v10, v11, v00, depth);      // east
    }

    Framebuffer& fb_;
    const Frame& f_;
    const HeightmapPatch& patch_;
    const bool all_defined_;
    Scratch& s_;
    const int n_;  // corners per side
    bool memo_ = false;
    GridVertex scratch_vertex_;
};

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

// The side (texels) below which a block cut by undefined texels is not split further: about a
// pixel, for a LOD `step` whose blocks are about lod_quad_px pixels (1 when texels are larger).
int smallest_block(int step, float lod_quad_px) {
    int side = step;
    for (float px = lod_quad_px; side > 1 && px > 1.0f; px /= 2.0f) side /= 2;
    return side;
}

void draw_patch(Framebuffer& fb, const Frame& f, const HeightmapPatch& patch, Scratch& scratch) {
    const PatchStats stats = patch_stats(patch);
    if (!stats.any_defined() || !patch_in_view(f, patch, stats)) return;
    const HeightmapPassSettings& settings = *f.settings;
    const int step = settings.fixed_step > 0
                         ? std::min(settings.fixed_step, patch.size)
                         : lod_step(patch, stats.z_min, stats.z_max, *f.camera, settings.lod_quad_px);
    const int min_side = settings.fixed_step > 0 ? 1 : smallest_block(step, settings.lod_quad_px);
    PatchDraw draw(fb, f, patch, stats.all_defined, scratch);
    for (int j = 0; j < patch.size; j += step) {
        for (int i = 0; i < patch.size; i += step) {
            draw.draw_block(i, std::min(i + step, patch.size), j, std::min(j + step, patch.size), min_side);
        }
    }
}

// Row y's horizontal minimum of three: out[x] = min(row[x - 1], row[x], row[x + 1]) (kEmpty off the image).
void row_min3(const Framebuffer& fb, int y, std::vector<std::uint64_t>& out) {
    const int w = fb.width();
    out.assign(static_cast<std::size_t>(w), kEmpty);
    if (y < 0 || y >= fb.height()) return;
    const std::uint64_t* row = fb.data() + static_cast<std::size_t>(y) * w;
    for (int x = 0; x < w; ++x) {
        out[x] = std::min({row[x], x > 0 ? row[x - 1] : kEmpty, x + 1 < w ? row[x + 1] : kEmpty});
    }
}

// Pixels the surface's outline passes through without covering their centres: an empty pixel
// next to (8-neighbourhood) a drawn one takes the nearest of its drawn neighbours. Decided from
// the pass's output alone (fills do not spread), in bands over the pool, then written.
void fill_outline(Framebuffer& fb, ThreadPool& pool) {
    const int w = fb.width(), h = fb.height();
    const std::size_t bands = std::min<std::size_t>(static_cast<std::size_t>(h), std::size_t{pool.size()} * 4);
    std::vector<std::vector<std::pair<int, std::uint64_t>>> fills(bands);  // (pixel index, fragment)
    pool.for_each(bands, [&](std::size_t b) {
        const int y0 = static_cast<int>(b * h / bands), y1 = static_cast<int>((b + 1) * h / bands);
        std::vector<std::uint64_t> above, here, below;  // row_min3 of y - 1, y, y + 1
        row_min3(fb, y0 - 1, above);
        row_min3(fb, y0, here);
        for (int y = y0; y < y1; ++y) {
            row_min3(fb, y + 1, below);
            const std::uint64_t* row = fb.data() + static_cast<std::size_t>(y) * w;
            for (int x = 0; x < w; ++x) {
                if (row[x] != kEmpty) continue;
                const std::uint64_t nearest = std::min({above[x], here[x], below[x]});
                if (nearest != kEmpty) fills[b].emplace_back(y * w + x, nearest);
            }
            std::swap(above, here);
            std::swap(here, below);
        }
    });
    for (const auto& band : fills) {
        for (const auto& [pixel, fragment] : band) fb.write_packed(pixel % w, pixel / w, fragment);
    }
}

}  // namespace

float level_gain(float sun_z, float ambient) {
    const float level = ambient + (1.0f - ambient) * std::max(0.0f, sun_z);
    return level > 0.0f ? 1.0f / level : 1.0f;
}

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
    if (settings.fill_outline) fill_outline(fb, pool);
}

}  // namespace lidarscout::render
