// The CUDA rasterizer's kernels, the GPU form of the CPU passes in src/render/ with the same
// arithmetic (the plugin is compiled with --fmad=false so that float expressions round as on
// the CPU): the point pass (one thread block per chunk of points), the heightmap pass (per
// patch statistics, culling and LOD step; the corner grid; triangles, small ones rasterized
// by one thread each and large ones queued for a cooperative kernel in which a whole block
// shares the pixels of one triangle) and the resolve with eye-dome lighting. The small math of
// camera, colour ramps and triangle setup is re-expressed here for the device (the CPU code
// keeps it in anonymous namespaces and std:: containers); each helper names its CPU original.
#include "render/cuda/raster_kernels.hpp"

#include <cmath>
#include <cstdint>

namespace lidarscout::render::cuda {
namespace {

constexpr int kThreads = 256;
constexpr int kSubBits = 8;  // triangle_raster.cpp: 1/256 pixel
constexpr long long kOne = 1LL << kSubBits;
constexpr long long kHalf = kOne / 2;
constexpr float kGuardBandPx = 1 << 20;
constexpr long long kSmallTrianglePixels = 256;  // larger bounding boxes go to the queue
constexpr float kUntexturedGrey = 170.0f;
constexpr int kRampSize = 1024;
constexpr float kEdlScale = 100.0f;
constexpr float kNoDepth = -1.0f;
constexpr Fragment kEmpty = ~0ull;

// --- framebuffer and colours (framebuffer.hpp, colour_modes.hpp) --------------------------

__device__ std::uint32_t pack_rgba(unsigned r, unsigned g, unsigned b) { return r | g << 8 | b << 16 | 255u << 24; }
__device__ unsigned red(std::uint32_t c) { return c & 0xff; }
__device__ unsigned green(std::uint32_t c) { return (c >> 8) & 0xff; }
__device__ unsigned blue(std::uint32_t c) { return (c >> 16) & 0xff; }

__device__ Fragment pack_fragment(float depth, std::uint32_t rgba) {
    return static_cast<Fragment>(__float_as_uint(depth)) << 32 | rgba;
}

__device__ void write(const Target& t, int x, int y, Fragment value) {
    atomicMin(t.fb + static_cast<std::size_t>(y) * t.width + x, value);
}

// Palette::ElevationMap.
__device__ std::uint32_t ramp_colour(const DeviceColours& c, float offset, float dz) {
    float i = (dz + offset) * c.ramp_scale;
    if (!(i >= 0.0f)) i = 0.0f;
    if (i > kRampSize - 1) i = kRampSize - 1;
    return c.ramp[static_cast<int>(i)];
}

__device__ std::uint32_t point_colour(const DeviceColours& c, const LsrPoint& p, float elevation_offset) {
    switch (c.mode) {
        case LSR_COLOUR_ELEVATION: return ramp_colour(c, elevation_offset, p.dz);
        case LSR_COLOUR_INTENSITY: return c.intensity[p.intensity];
        case LSR_COLOUR_CLASSIFICATION: return c.classes[p.classification];
        default: return pack_rgba(p.r, p.g, p.b);
    }
}

// render::PointFilter: class, return kinds (unknown passes), intensity.
__device__ bool keeps(const LsrPointFilter& f, const LsrPoint& p) {
    if (!f.active) return true;
    return ((f.classes[p.classification >> 5] >> (p.classification & 31)) & 1u) &&
           (p.returns == 0 || (p.returns & f.return_kinds) != 0) && p.intensity >= f.intensity_min &&
           p.intensity <= f.intensity_max;
}

__device__ float row_dot(const float* row, float x, float y, float z) {
    return row[0] * x + row[1] * y + row[2] * z + row[3];
}

// --- point pass (point_pass.cpp) ------------------------------------------------------------

__device__ void draw_point(const Target& t, float x, float y, Fragment value, int size) {
    if (size == 1) {
        if (!(x >= 0.0f && x < t.width && y >= 0.0f && y < t.height)) return;
        write(t, static_cast<int>(x), static_cast<int>(y), value);
        return;
    }
    const float margin = static_cast<float>(size);
    if (!(x >= -margin && x < t.width + margin && y >= -margin && y < t.height + margin)) return;
    const int half = (size - 1) / 2;
    const int x0 = static_cast<int>(floorf(x)) - half, y0 = static_cast<int>(floorf(y)) - half;
    for (int py = max(y0, 0); py <= min(y0 + size - 1, t.height - 1); ++py) {
        for (int px = max(x0, 0); px <= min(x0 + size - 1, t.width - 1); ++px) write(t, px, py, value);
    }
}

// A point's side: `size`, or with a size scale its spacing on screen within [size, max_size].
__device__ int point_side(const DeviceBatch& b, float inv_depth, int size, int max_size) {
    if (!(b.size_scale > 0.0f)) return size;
    return static_cast<int>(fminf(fmaxf(ceilf(b.size_scale * inv_depth), static_cast<float>(size)),
                                  static_cast<float>(max_size)));
}

__global__ void points_kernel(Target t, DeviceColours c, const DeviceBatch* batches, const PointJob* jobs, int size,
                              int max_size) {
    const PointJob job = jobs[blockIdx.x];
    const DeviceBatch b = batches[job.batch];
    const LsrPoint* points = b.points;
    for (std::uint64_t i = job.begin + threadIdx.x; i < job.end; i += blockDim.x) {
        const LsrPoint p = points[i];
        if (!keeps(c.filter, p)) continue;
        const float w = row_dot(b.screen.depth, p.dx, p.dy, p.dz);
        if (!(w >= t.near_m && w <= t.far_m)) continue;
        const float inv = 1.0f / w;
        const float x = row_dot(b.screen.sx, p.dx, p.dy, p.dz) * inv, y = row_dot(b.screen.sy, p.dx, p.dy, p.dz) * inv;
        const int side = point_side(b, inv, size, max_size);
        draw_point(t, x, y, pack_fragment(w, point_colour(c, p, b.elevation_offset)), side);
    }
}

// --- triangles (triangle_raster.cpp) --------------------------------------------------------

struct Setup {
    long long px[3], py[3];
    long long bias[3];  // per edge (opposite vertex i)
    int x0, x1, y0, y1;
    float inv_area, inv_depth[3], r[3], g[3], b[3];
};

__device__ long long edge(long long ax, long long ay, long long bx, long long by, long long px, long long py) {
    return (bx - ax) * (py - ay) - (by - ay) * (px - ax);
}

__device__ long long tie_bias(long long ax, long long ay, long long bx, long long by) {
    const long long dx = bx - ax, dy = by - ay;
    return (dy < 0 || (dy == 0 && dx > 0)) ? 0 : -1;
}

__device__ void pixel_span(long long lo, long long hi, int size, int& first, int& last) {
    const long long f = (lo - kHalf + kOne - 1) >> kSubBits, l = (hi - kHalf) >> kSubBits;
    first = static_cast<int>(f > 0 ? f : 0);
    last = static_cast<int>(l < size - 1 ? l : size - 1);
}

__device__ bool in_guard_band(const RasterVertex& v) { return fabsf(v.x) < kGuardBandPx && fabsf(v.y) < kGuardBandPx; }

// draw_triangle's setup: snapping, orientation, bounding box, interpolation constants. False
// when nothing is drawn.
__device__ bool setup_triangle(const RasterVertex* in, float shade, float depth_scale, const Target& t, Setup& s) {
    if (!in_guard_band(in[0]) || !in_guard_band(in[1]) || !in_guard_band(in[2])) return false;
    const RasterVertex* v[3] = {&in[0], &in[1], &in[2]};
    for (int i = 0; i < 3; ++i) {
        s.px[i] = llrintf(v[i]->x * static_cast<float>(kOne));
        s.py[i] = llrintf(v[i]->y * static_cast<float>(kOne));
    }
    long long area = edge(s.px[0], s.py[0], s.px[1], s.py[1], s.px[2], s.py[2]);
    if (area == 0) return false;
    if (area < 0) {
        long long x = s.px[1], y = s.py[1];
        s.px[1] = s.px[2], s.py[1] = s.py[2], s.px[2] = x, s.py[2] = y;
        const RasterVertex* tmp = v[1];
        v[1] = v[2], v[2] = tmp;
        area = -area;
    }
    pixel_span(min(s.px[0], min(s.px[1], s.px[2])), max(s.px[0], max(s.px[1], s.px[2])), t.width, s.x0, s.x1);
    pixel_span(min(s.py[0], min(s.py[1], s.py[2])), max(s.py[0], max(s.py[1], s.py[2])), t.height, s.y0, s.y1);
    if (s.x0 > s.x1 || s.y0 > s.y1) return false;
    for (int i = 0; i < 3; ++i) {
        const int a = (i + 1) % 3, b = (i + 2) % 3;
        s.bias[i] = tie_bias(s.px[a], s.py[a], s.px[b], s.py[b]);
        s.inv_depth[i] = 1.0f / (v[i]->depth * depth_scale);
        s.r[i] = v[i]->r * shade, s.g[i] = v[i]->g * shade, s.b[i] = v[i]->b * shade;
    }
    s.inv_area = 1.0f / static_cast<float>(area);
    return true;
}

__device__ unsigned channel(float l0, float l1, float l2, const float* c) {
    float v = l0 * c[0] + l1 * c[1] + l2 * c[2];
    v = v < 0.0f ? 0.0f : (255.0f < v ? 255.0f : v);  // std::clamp
    return static_cast<unsigned>(static_cast<int>(v + 0.5f)) & 0xff;
}

// The edge functions at the pixel centre, evaluated directly (the CPU steps them along rows;
// both are exact integers, so they agree).
__device__ void shade_pixel(const Target& t, const Setup& s, int x, int y) {
    const long long cx = x * kOne + kHalf, cy = y * kOne + kHalf;
    const long long w0 = edge(s.px[1], s.py[1], s.px[2], s.py[2], cx, cy);
    const long long w1 = edge(s.px[2], s.py[2], s.px[0], s.py[0], cx, cy);
    const long long w2 = edge(s.px[0], s.py[0], s.px[1], s.py[1], cx, cy);
    if (((w0 + s.bias[0]) | (w1 + s.bias[1]) | (w2 + s.bias[2])) < 0) return;
    const float l0 = static_cast<float>(w0) * s.inv_area, l1 = static_cast<float>(w1) * s.inv_area;
    const float l2 = static_cast<float>(w2) * s.inv_area;
    const float depth = 1.0f / (l0 * s.inv_depth[0] + l1 * s.inv_depth[1] + l2 * s.inv_depth[2]);
    write(t, x, y, pack_fragment(depth, pack_rgba(channel(l0, l1, l2, s.r), channel(l0, l1, l2, s.g),
                                                  channel(l0, l1, l2, s.b))));
}

__device__ long long box_pixels(const Setup& s) {
    return static_cast<long long>(s.x1 - s.x0 + 1) * (s.y1 - s.y0 + 1);
}

// A small triangle is drawn by the calling thread; a large one goes to the queue (or is drawn
// here when the queue is full).
__device__ void emit_triangle(const Target& t, const TriangleQueue& q, const RasterVertex& a, const RasterVertex& b,
                              const RasterVertex& c, float shade, float depth_scale) {
    const RasterVertex v[3] = {a, b, c};
    Setup s;
    if (!setup_triangle(v, shade, depth_scale, t, s)) return;
    if (box_pixels(s) > kSmallTrianglePixels) {
        const unsigned int slot = atomicAdd(q.count, 1u);
        if (slot < q.capacity) {
            q.items[slot] = QueuedTriangle{{a, b, c}, shade, depth_scale};
            return;
        }
    }
    for (int y = s.y0; y <= s.y1; ++y) {
        for (int x = s.x0; x <= s.x1; ++x) shade_pixel(t, s, x, y);
    }
}

__global__ void queued_triangles_kernel(Target t, TriangleQueue q) {
    const unsigned int count = min(*q.count, q.capacity);
    for (unsigned int k = blockIdx.x; k < count; k += gridDim.x) {
        const QueuedTriangle tri = q.items[k];
        Setup s;
        if (!setup_triangle(tri.v, tri.shade, tri.depth_scale, t, s)) continue;
        const int width = s.x1 - s.x0 + 1;
        const long long pixels = box_pixels(s);
        for (long long i = threadIdx.x; i < pixels; i += blockDim.x) {
            shade_pixel(t, s, s.x0 + static_cast<int>(i % width), s.y0 + static_cast<int>(i / width));
        }
    }
}

// --- heightmap pass (heightmap_pass.cpp) ----------------------------------------------------

__device__ RasterVertex project(const HeightmapFrame& h, float x, float y, float z, float r, float g, float b) {
    RasterVertex v;
    v.depth = row_dot(h.screen.depth, x, y, z);
    const float inv = 1.0f / v.depth;
    v.x = row_dot(h.screen.sx, x, y, z) * inv;
    v.y = row_dot(h.screen.sy, x, y, z) * inv;
    v.r = r, v.g = g, v.b = b;
    return v;
}

// box_in_view.
__device__ bool box_in_view(const HeightmapFrame& h, const Target& t, const float* lo, const float* hi) {
    int outside[6] = {0, 0, 0, 0, 0, 0};
    for (int corner = 0; corner < 8; ++corner) {
        const float x = (corner & 1) ? hi[0] : lo[0], y = (corner & 2) ? hi[1] : lo[1];
        const float z = (corner & 4) ? hi[2] : lo[2];
        const float sx = row_dot(h.screen.sx, x, y, z), sy = row_dot(h.screen.sy, x, y, z);
        const float w = row_dot(h.screen.depth, x, y, z);
        const float planes[6] = {sx, t.width * w - sx, sy, t.height * w - sy, w - t.near_m, t.far_m - w};
        for (int p = 0; p < 6; ++p) outside[p] += planes[p] < 0.0f;
    }
    for (int p = 0; p < 6; ++p) {
        if (outside[p] == 8) return false;
    }
    return true;
}

// std::hypot(x, y, z) as libstdc++ computes it, so the LOD choice matches the CPU's.
__device__ double hypot3(double x, double y, double z) {
    x = fabs(x), y = fabs(y), z = fabs(z);
    const double a = x < y ? (y < z ? z : y) : (x < z ? z : x);
    if (a == 0.0) return 0.0;
    return a * sqrt((x / a) * (x / a) + (y / a) * (y / a) + (z / a) * (z / a));
}

__device__ double gap(double lo, double hi, double p) { return fmax(fmax(lo - p, 0.0), p - hi); }

// lod_step.
__device__ int lod_step(const HeightmapFrame& h, const DevicePatch& p, double z_min, double z_max) {
    const double side = p.size * p.texel_m;
    const double distance = hypot3(gap(p.origin_x, p.origin_x + side, h.camera_x),
                                   gap(p.origin_y, p.origin_y + side, h.camera_y), gap(z_min, z_max, h.camera_z));
    const double texel_px = p.texel_m * h.focal_px / (distance < h.near_m ? h.near_m : distance);
    int step = 1;
    while (step * 2 <= p.size && texel_px * step * 2 <= h.lod_quad_px) step *= 2;
    return step;
}

__device__ bool patch_in_view(const HeightmapFrame& h, const Target& t, const DevicePatch& p, float z_min,
                              float z_max) {
    const double side = p.size * p.texel_m;
    const float lo[3] = {static_cast<float>(p.origin_x - h.camera_x), static_cast<float>(p.origin_y - h.camera_y),
                         static_cast<float>(static_cast<double>(z_min) - h.camera_z)};
    const float hi[3] = {static_cast<float>(p.origin_x + side - h.camera_x),
                         static_cast<float>(p.origin_y + side - h.camera_y),
                         static_cast<float>(static_cast<double>(z_max) - h.camera_z)};
    return box_in_view(h, t, lo, hi);
}

__device__ int corner_at(int k, int step, int size) { return min(k * step, size); }
__device__ int corner_count(int step, int size) { return (size + step - 1) / step + 1; }

// One block per patch: height range (a block reduction), culling and the LOD step.
__global__ void patch_info_kernel(HeightmapFrame h, Target t, PatchInfo* info) {
    __shared__ float s_lo[kThreads], s_hi[kThreads];
    const DevicePatch p = h.patches[blockIdx.x];
    const float* heights = p.heights;
    float lo = INFINITY, hi = -INFINITY;
    int defined = 1;
    for (int k = threadIdx.x; k < p.size * p.size; k += blockDim.x) {
        const float v = heights[k];
        if (isnan(v)) {
            defined = 0;
        } else {
            lo = fminf(lo, v), hi = fmaxf(hi, v);
        }
    }
    s_lo[threadIdx.x] = lo, s_hi[threadIdx.x] = hi;
    const int all_defined = __syncthreads_and(defined);
    for (int stride = blockDim.x / 2; stride > 0; stride /= 2) {
        if (threadIdx.x < stride) {
            s_lo[threadIdx.x] = fminf(s_lo[threadIdx.x], s_lo[threadIdx.x + stride]);
            s_hi[threadIdx.x] = fmaxf(s_hi[threadIdx.x], s_hi[threadIdx.x + stride]);
        }
        __syncthreads();
    }
    if (threadIdx.x != 0) return;
    PatchInfo out{s_lo[0], s_hi[0], all_defined, 0, 1, 0};
    if (out.z_min <= out.z_max && patch_in_view(h, t, p, out.z_min, out.z_max)) {
        out.visible = 1;
        out.step = h.fixed_step > 0 ? min(h.fixed_step, p.size) : lod_step(h, p, out.z_min, out.z_max);
        out.blocks = corner_count(out.step, p.size) - 1;
    }
    info[blockIdx.x] = out;
}

// extrapolated_height.
__device__ float extrapolated_height(const float* heights, int size, int ci, int cj, float fallback) {
    if (size < 2) return fallback;
    const int i0 = min(max(ci - 1, 0), size - 2), j0 = min(max(cj - 1, 0), size - 2);
    const float u = (ci - 0.5f) - i0, v = (cj - 0.5f) - j0;
    const float h00 = heights[j0 * size + i0], h10 = heights[j0 * size + i0 + 1];
    const float h01 = heights[(j0 + 1) * size + i0], h11 = heights[(j0 + 1) * size + i0 + 1];
    const float h = (1 - v) * ((1 - u) * h00 + u * h10) + v * ((1 - u) * h01 + u * h11);
    return isnan(h) ? fallback : h;
}

// texel_tinted and corner_attributes.
__device__ bool texel_tinted(const DevicePatch& p, int t) {
    return p.tint == LSR_TINT_ALL || (p.tint == LSR_TINT_MARKED && p.colours && (p.colours[t] >> 24) < 255u);
}

__device__ bool corner_attributes(const DevicePatch& p, const std::uint32_t* colours, int ci, int cj,
                                  float& height, float* rgb, float& tinted_share) {
    const float* heights = p.heights;
    const int size = p.size;
    float sum_h = 0.0f, sum_c[3] = {0.0f, 0.0f, 0.0f};
    int n = 0, tinted = 0;
    for (int j = max(cj - 1, 0); j <= min(cj, size - 1); ++j) {
        for (int i = max(ci - 1, 0); i <= min(ci, size - 1); ++i) {
            const int t = j * size + i;
            if (isnan(heights[t])) continue;
            sum_h += heights[t];
            if (colours) {
                const std::uint32_t c = colours[t];
                sum_c[0] += red(c), sum_c[1] += green(c), sum_c[2] += blue(c);
            }
            tinted += texel_tinted(p, t);
            ++n;
        }
    }
    if (n == 0) return false;
    const bool boundary = ci == 0 || cj == 0 || ci == size || cj == size;
    height = boundary ? extrapolated_height(heights, size, ci, cj, sum_h / n) : sum_h / n;
    for (int k = 0; k < 3; ++k) rgb[k] = colours ? sum_c[k] / n : kUntexturedGrey;
    tinted_share = static_cast<float>(tinted) / n;
    return true;
}

__device__ float corner_offset(double origin, double camera, int corner, double texel_m) {
    return static_cast<float>((origin - camera) + corner * texel_m);
}

__device__ GridVertex grid_vertex(const HeightmapFrame& h, const Target& t, const DeviceColours& c,
                                  const DevicePatch& p, int step, int ki, int kj) {
    GridVertex v{};
    const int ci = corner_at(ki, step, p.size), cj = corner_at(kj, step, p.size);
    const std::uint32_t* colours = p.textured ? p.colours : nullptr;
    float height = 0.0f, rgb[3], tinted = 0.0f;
    if (!corner_attributes(p, colours, ci, cj, height, rgb, tinted)) return v;
    v.x = corner_offset(p.origin_x, h.camera_x, ci, p.texel_m);
    v.y = corner_offset(p.origin_y, h.camera_y, cj, p.texel_m);
    v.z = static_cast<float>(static_cast<double>(height) - h.camera_z);
    if (c.mode == LSR_COLOUR_ELEVATION) {
        const std::uint32_t e = ramp_colour(c, c.heightmap_offset, height);
        rgb[0] = red(e), rgb[1] = green(e), rgb[2] = blue(e);
    }
    const float mix = tinted * h.tint_strength;
    for (int k = 0; k < 3; ++k) rgb[k] += (h.tint_rgb[k] - rgb[k]) * mix;
    const RasterVertex s = project(h, v.x, v.y, v.z, rgb[0], rgb[1], rgb[2]);
    v.sx = s.x, v.sy = s.y, v.depth = s.depth, v.r = s.r, v.g = s.g, v.b = s.b;
    v.drawable = s.depth >= t.near_m;
    return v;
}

__device__ bool texels_defined(const float* heights, int size, int i0, int i1, int j0, int j1) {
    for (int j = j0; j < j1; ++j) {
        for (int i = i0; i < i1; ++i) {
            if (isnan(heights[j * size + i])) return false;
        }
    }
    return true;
}

// One block per visible patch: its corner grid at its LOD step, and which blocks are wholly defined.
__global__ void patch_grid_kernel(HeightmapFrame h, Target t, DeviceColours c, const PatchInfo* info,
                                  const PatchWork* work, GridVertex* grid, unsigned char* drawn) {
    const PatchWork w = work[blockIdx.x];
    const DevicePatch p = h.patches[w.patch];
    const PatchInfo pi = info[w.patch];
    const int n = pi.blocks + 1;
    for (int k = threadIdx.x; k < n * n; k += blockDim.x) {
        grid[w.grid + k] = grid_vertex(h, t, c, p, pi.step, k % n, k / n);
    }
    const int blocks = pi.blocks;
    const float* heights = p.heights;
    for (int k = threadIdx.x; k < blocks * blocks; k += blockDim.x) {
        const int bi = k % blocks, bj = k / blocks;
        drawn[w.drawn + k] = pi.all_defined ||
                             texels_defined(heights, p.size, corner_at(bi, pi.step, p.size),
                                            corner_at(bi + 1, pi.step, p.size), corner_at(bj, pi.step, p.size),
                                            corner_at(bj + 1, pi.step, p.size));
    }
}

__device__ float3 normalised(float x, float y, float z) {
    const float length = sqrtf(x * x + y * y + z * z);
    if (!(length > 0.0f)) return make_float3(0.0f, 0.0f, 1.0f);
    return make_float3(x / length, y / length, z / length);
}

// face_shade.
__device__ float face_shade(const HeightmapFrame& h, const GridVertex& a, const GridVertex& b, const GridVertex& c) {
    const float ux = b.x - a.x, uy = b.y - a.y, uz = b.z - a.z;
    const float vx = c.x - a.x, vy = c.y - a.y, vz = c.z - a.z;
    float3 n = normalised(uy * vz - uz * vy, uz * vx - ux * vz, ux * vy - uy * vx);
    if (n.z < 0.0f) n = make_float3(-n.x, -n.y, -n.z);
    const float lambert = fmaxf(0.0f, n.x * h.sun[0] + n.y * h.sun[1] + n.z * h.sun[2]);
    return (h.ambient + (1.0f - h.ambient) * lambert) * h.level_gain;
}

__device__ RasterVertex screen_of(const GridVertex& v) { return RasterVertex{v.sx, v.sy, v.depth, v.r, v.g, v.b}; }

__device__ void draw_face(const HeightmapFrame& h, const Target& t, const TriangleQueue& q, const GridVertex& a,
                          const GridVertex& b, const GridVertex& c) {
    if (!(a.drawable && b.drawable && c.drawable)) return;
    emit_triangle(t, q, screen_of(a), screen_of(b), screen_of(c), face_shade(h, a, b, c), h.depth_scale);
}

// draw_skirt: a vertical strip `depth` metres down from the boundary edge a-b.
__device__ void draw_skirt(const HeightmapFrame& h, const Target& t, const TriangleQueue& q, const GridVertex& a,
                           const GridVertex& b, const GridVertex& inner, float depth) {
    if (!(a.drawable && b.drawable && inner.drawable)) return;
    const RasterVertex a_low = project(h, a.x, a.y, a.z - depth, a.r, a.g, a.b);
    const RasterVertex b_low = project(h, b.x, b.y, b.z - depth, b.r, b.g, b.b);
    if (!(a_low.depth >= t.near_m && b_low.depth >= t.near_m)) return;
    const float shade = face_shade(h, a, b, inner);
    emit_triangle(t, q, screen_of(a), screen_of(b), b_low, shade, h.depth_scale);
    emit_triangle(t, q, screen_of(a), b_low, a_low, shade, h.depth_scale);
}

// One skirt segment under a wholly defined block: side 0 south, 1 north, 2 west, 3 east.
__device__ void skirt_segment(const HeightmapFrame& h, const Target& t, const TriangleQueue& q, const GridVertex* g,
                              const unsigned char* drawn, int n, int side, int k, float depth) {
    const auto vertex = [&](int ki, int kj) -> const GridVertex& { return g[kj * (n + 1) + ki]; };
    const auto is_drawn = [&](int bi, int bj) { return drawn[bj * n + bi] != 0; };
    if (side == 0 && is_drawn(k, 0)) draw_skirt(h, t, q, vertex(k, 0), vertex(k + 1, 0), vertex(k + 1, 1), depth);
    if (side == 1 && is_drawn(k, n - 1)) {
        draw_skirt(h, t, q, vertex(k, n), vertex(k + 1, n), vertex(k, n - 1), depth);
    }
    if (side == 2 && is_drawn(0, k)) draw_skirt(h, t, q, vertex(0, k), vertex(0, k + 1), vertex(1, k + 1), depth);
    if (side == 3 && is_drawn(n - 1, k)) {
        draw_skirt(h, t, q, vertex(n, k), vertex(n, k + 1), vertex(n - 1, k), depth);
    }
}

// The undefined texels of [i0, i1) x [j0, j1).
__device__ int undefined_in(const float* heights, int size, int i0, int i1, int j0, int j1) {
    int n = 0;
    for (int j = j0; j < j1; ++j) {
        for (int i = i0; i < i1; ++i) n += isnan(heights[j * size + i]) ? 1 : 0;
    }
    return n;
}

// draw_quad (heightmap_pass.cpp): two faces over texels [i0, i1) x [j0, j1), skirts on the patch edges.
__device__ void draw_quad(const HeightmapFrame& h, const Target& t, const DeviceColours& c, const TriangleQueue& q,
                          const DevicePatch& p, int i0, int i1, int j0, int j1) {
    const GridVertex v00 = grid_vertex(h, t, c, p, 1, i0, j0), v10 = grid_vertex(h, t, c, p, 1, i1, j0);
    const GridVertex v01 = grid_vertex(h, t, c, p, 1, i0, j1), v11 = grid_vertex(h, t, c, p, 1, i1, j1);
    draw_face(h, t, q, v00, v10, v11);
    draw_face(h, t, q, v00, v11, v01);
    const float depth = static_cast<float>(h.skirt_quads * max(i1 - i0, j1 - j0) * p.texel_m);
    if (!(depth > 0.0f)) return;
    if (j0 == 0) draw_skirt(h, t, q, v00, v10, v11, depth);
    if (j1 == p.size) draw_skirt(h, t, q, v01, v11, v00, depth);
    if (i0 == 0) draw_skirt(h, t, q, v00, v01, v11, depth);
    if (i1 == p.size) draw_skirt(h, t, q, v10, v11, v00, depth);
}

// smallest_block (heightmap_pass.cpp): about a pixel, for a LOD step whose blocks are lod_quad_px.
__device__ int smallest_block(const HeightmapFrame& h, int step) {
    if (h.fixed_step > 0) return 1;
    int side = step;
    for (float px = h.lod_quad_px; side > 1 && px > 1.0f; px /= 2.0f) side /= 2;
    return side;
}

// PatchDraw::draw_block (heightmap_pass.cpp) for a block with some undefined texels: split in four
// until blocks of min_side, drawn when at least half defined; fully defined parts drawn whole.
__device__ void draw_partial_block(const HeightmapFrame& h, const Target& t, const DeviceColours& c,
                                   const TriangleQueue& q, const DevicePatch& p, int i0, int i1, int j0, int j1,
                                   int min_side) {
    // (i0, i1, j0, j1), depth first: at most 3 per level of splitting plus one; a patch is at most
    // 4,096 texels a side (backend.cpp refuses larger ones), so it splits at most 12 times (37 entries).
    constexpr int kStack = 64;
    int4 stack[kStack];
    int top = 0;
    stack[top++] = make_int4(i0, i1, j0, j1);
    while (top > 0) {
        const int4 b = stack[--top];
        const int undefined = undefined_in(p.heights, p.size, b.x, b.y, b.z, b.w);
        const int texels = (b.y - b.x) * (b.w - b.z);
        if (undefined == 0) {
            draw_quad(h, t, c, q, p, b.x, b.y, b.z, b.w);
            continue;
        }
        if (undefined == texels) continue;
        if (b.y - b.x <= min_side && b.w - b.z <= min_side) {
            if (2 * undefined <= texels) draw_quad(h, t, c, q, p, b.x, b.y, b.z, b.w);
            continue;
        }
        const int im = b.y - b.x > 1 ? (b.x + b.y) / 2 : b.y, jm = b.w - b.z > 1 ? (b.z + b.w) / 2 : b.w;
        if (top + 4 > kStack) __trap();  // not reached (see above)
        if (im < b.y && jm < b.w) stack[top++] = make_int4(im, b.y, jm, b.w);
        if (jm < b.w) stack[top++] = make_int4(b.x, im, jm, b.w);
        if (im < b.y) stack[top++] = make_int4(im, b.y, b.z, jm);
        stack[top++] = make_int4(b.x, im, b.z, jm);
    }
}

// One block per visible patch; one thread per block of texels (two faces) or skirt segment.
// Blocks with some undefined texels are split (draw_partial_block).
__global__ void patch_triangles_kernel(HeightmapFrame h, Target t, DeviceColours c, const PatchInfo* info,
                                       const PatchWork* work, const GridVertex* grid, const unsigned char* drawn,
                                       TriangleQueue q) {
    const PatchWork w = work[blockIdx.x];
    const DevicePatch p = h.patches[w.patch];
    const PatchInfo pi = info[w.patch];
    const int n = pi.blocks;
    const GridVertex* g = grid + w.grid;
    const unsigned char* d = drawn + w.drawn;
    const float skirt_depth = static_cast<float>(h.skirt_quads * pi.step * p.texel_m);
    const int items = n * n + (h.skirt_quads > 0.0f ? 4 * n : 0);
    for (int k = threadIdx.x; k < items; k += blockDim.x) {
        if (k >= n * n) {
            skirt_segment(h, t, q, g, d, n, (k - n * n) / n, (k - n * n) % n, skirt_depth);
            continue;
        }
        const int bi = k % n, bj = k / n;
        if (!d[k]) {
            draw_partial_block(h, t, c, q, p, corner_at(bi, pi.step, p.size), corner_at(bi + 1, pi.step, p.size),
                               corner_at(bj, pi.step, p.size), corner_at(bj + 1, pi.step, p.size),
                               smallest_block(h, pi.step));
            continue;
        }
        const GridVertex &v00 = g[bj * (n + 1) + bi], &v10 = g[bj * (n + 1) + bi + 1];
        const GridVertex &v01 = g[(bj + 1) * (n + 1) + bi], &v11 = g[(bj + 1) * (n + 1) + bi + 1];
        draw_face(h, t, q, v00, v10, v11);
        draw_face(h, t, q, v00, v11, v01);
    }
}

// --- resolve (resolve.cpp) ------------------------------------------------------------------

__global__ void resolve_copy_kernel(Target t, std::uint32_t background, std::uint32_t* image, float* log_depth,
                                    unsigned long long* drawn) {
    const std::size_t n = static_cast<std::size_t>(t.width) * t.height;
    const std::size_t i = static_cast<std::size_t>(blockIdx.x) * blockDim.x + threadIdx.x;
    const Fragment v = i < n ? t.fb[i] : kEmpty;
    if (i < n) {
        image[i] = v == kEmpty ? background : static_cast<std::uint32_t>(v);
        if (log_depth) log_depth[i] = v == kEmpty ? kNoDepth : log2f(__uint_as_float(static_cast<unsigned>(v >> 32)));
    }
    const unsigned int ballot = __ballot_sync(0xffffffffu, v != kEmpty);
    if ((threadIdx.x & 31) == 0 && ballot) atomicAdd(drawn, static_cast<unsigned long long>(__popc(ballot)));
}

__device__ std::uint32_t darken(std::uint32_t rgba, float factor) {
    const auto scale = [factor](unsigned c) {
        return static_cast<unsigned>(static_cast<int>(c * factor + 0.5f)) & 0xff;
    };
    return scale(red(rgba)) | scale(green(rgba)) << 8 | scale(blue(rgba)) << 16 | (rgba & 0xff000000u);
}

__global__ void resolve_edl_kernel(Target t, LsrResolve r, const float* log_depth, std::uint32_t* image) {
    const int x = blockIdx.x * blockDim.x + threadIdx.x, y = blockIdx.y;
    if (x >= t.width) return;
    const std::size_t i = static_cast<std::size_t>(y) * t.width + x;
    const float d = log_depth[i];
    if (d == kNoDepth) return;
    const int rad = r.edl_radius_px;
    const int nx[4] = {x - rad, x + rad, x, x}, ny[4] = {y, y, y - rad, y + rad};
    float sum = 0.0f;
    for (int k = 0; k < 4; ++k) {
        if (nx[k] < 0 || nx[k] >= t.width || ny[k] < 0 || ny[k] >= t.height) continue;
        const float n = log_depth[static_cast<std::size_t>(ny[k]) * t.width + nx[k]];
        if (n != kNoDepth) sum += fmaxf(0.0f, d - n);
    }
    const float response = 0.25f * sum;
    if (response > 0.0f) image[i] = darken(image[i], expf(-(kEdlScale * r.edl_strength) * response));
}

// fill_outline (heightmap_pass.hpp): each empty pixel beside (8-neighbourhood) a drawn one gets
// the nearest of them, decided from the pass's output alone into `fills`, then written.
__global__ void outline_find_kernel(Target t, Fragment* fills) {
    const int i = blockIdx.x * blockDim.x + threadIdx.x;
    if (i >= t.width * t.height) return;
    const int x = i % t.width, y = i / t.width;
    Fragment nearest = kEmpty;
    if (t.fb[i] == kEmpty) {
        for (int ny = max(y - 1, 0); ny <= min(y + 1, t.height - 1); ++ny) {
            for (int nx = max(x - 1, 0); nx <= min(x + 1, t.width - 1); ++nx) {
                const Fragment v = t.fb[ny * t.width + nx];
                if (v < nearest) nearest = v;
            }
        }
    }
    fills[i] = nearest;
}

__global__ void outline_write_kernel(Target t, const Fragment* fills) {
    const int i = blockIdx.x * blockDim.x + threadIdx.x;
    if (i < t.width * t.height && fills[i] != kEmpty) t.fb[i] = fills[i];
}

unsigned int blocks_for(std::size_t n) { return static_cast<unsigned int>((n + kThreads - 1) / kThreads); }

}  // namespace

void launch_patch_info(const HeightmapFrame& h, const Target& t, std::uint32_t patches, PatchInfo* info,
                       cudaStream_t stream) {
    if (patches) patch_info_kernel<<<patches, kThreads, 0, stream>>>(h, t, info);
}

void launch_patch_grids(const HeightmapFrame& h, const Target& t, const DeviceColours& c, const PatchInfo* info,
                        const PatchWork* work, std::uint32_t count, GridVertex* grid, unsigned char* drawn,
                        cudaStream_t stream) {
    if (count) patch_grid_kernel<<<count, kThreads, 0, stream>>>(h, t, c, info, work, grid, drawn);
}

void launch_patch_triangles(const HeightmapFrame& h, const Target& t, const DeviceColours& c, const PatchInfo* info,
                            const PatchWork* work, std::uint32_t count, const GridVertex* grid,
                            const unsigned char* drawn, TriangleQueue queue, cudaStream_t stream) {
    if (count) patch_triangles_kernel<<<count, kThreads, 0, stream>>>(h, t, c, info, work, grid, drawn, queue);
}

void launch_queued_triangles(const Target& t, TriangleQueue queue, int blocks, cudaStream_t stream) {
    queued_triangles_kernel<<<blocks, kThreads, 0, stream>>>(t, queue);
}

void launch_fill_outline(const Target& t, Fragment* fills, cudaStream_t stream) {
    const std::size_t n = static_cast<std::size_t>(t.width) * t.height;
    outline_find_kernel<<<blocks_for(n), kThreads, 0, stream>>>(t, fills);
    outline_write_kernel<<<blocks_for(n), kThreads, 0, stream>>>(t, fills);
}

void launch_points(const Target& t, const DeviceColours& c, const DeviceBatch* batches, const PointJob* jobs,
                   std::uint64_t job_count, int point_size, int max_point_size, cudaStream_t stream) {
    if (job_count) {
        points_kernel<<<static_cast<unsigned int>(job_count), kThreads, 0, stream>>>(t, c, batches, jobs, point_size,
                                                                                     max_point_size);
    }
}

void launch_resolve(const Target& t, const LsrResolve& r, std::uint32_t* image, float* log_depth,
                    unsigned long long* drawn, cudaStream_t stream) {
    const std::size_t n = static_cast<std::size_t>(t.width) * t.height;
    const bool edl = r.edl_strength != 0.0f;
    resolve_copy_kernel<<<blocks_for(n), kThreads, 0, stream>>>(t, r.background, image, edl ? log_depth : nullptr,
                                                                drawn);
    if (edl) {
        const dim3 grid(blocks_for(static_cast<std::size_t>(t.width)), static_cast<unsigned int>(t.height));
        resolve_edl_kernel<<<grid, kThreads, 0, stream>>>(t, r, log_depth, image);
    }
}

}  // namespace lidarscout::render::cuda
