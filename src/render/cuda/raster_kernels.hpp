// The CUDA rasterizer's kernels as the plugin's host code launches them: the device-side
// descriptions of a frame's data (all pointers are device memory) and one launch function per
// pass. The semantics are those of the CPU passes in src/render/ (point_pass, heightmap_pass,
// triangle_raster, resolve); see raster_kernels.cu.
#pragma once

#include <cuda_runtime.h>

#include <cstdint>

#include "render/cuda/raster_abi.h"

namespace lidarscout::render::cuda {

using Fragment = unsigned long long;  // (depth bits << 32) | rgba, as render/framebuffer.hpp

struct Target {
    Fragment* fb;
    int width, height;
    float near_m, far_m;
};

struct DeviceColours {
    int mode;
    const std::uint32_t* ramp;
    float ramp_scale, heightmap_offset;
    const std::uint32_t* intensity;
    const std::uint32_t* classes;
    LsrPointFilter filter;  // the points drawn
};

// A batch of the point pass: its points in device memory (the frame's upload arena, or the
// copy kept from earlier frames).
struct DeviceBatch {
    LsrTransform screen;
    float elevation_offset;
    const LsrPoint* points;
    float size_scale;  // LsrBatch::size_scale
};

// One thread block's work: points [begin, end) of `batch`.
struct PointJob {
    std::uint32_t batch;
    std::uint64_t begin, end;
};

struct DevicePatch {
    double origin_x, origin_y, texel_m;
    int size;
    const float* heights;            // size x size, device memory
    const std::uint32_t* colours;    // size x size, device memory (used when textured)
    int textured;
    int tint;                        // LSR_TINT_*
};

// What the first heightmap kernel decides per patch.
struct PatchInfo {
    float z_min, z_max;
    int all_defined, visible;
    int step, blocks;  // LOD step; blocks per side (corner_count - 1)
};

// Where a visible patch's scratch lives (filled by the host from PatchInfo).
struct PatchWork {
    std::uint32_t patch;
    std::uint64_t grid;    // first grid vertex ((blocks + 1)^2 of them)
    std::uint64_t drawn;   // first block flag (blocks^2 of them)
};

struct GridVertex {
    float x, y, z;                    // camera-relative world position
    float sx, sy, depth, r, g, b;     // screen vertex (RasterVertex)
    int drawable;
};

struct RasterVertex {
    float x, y, depth, r, g, b;
};

// A large triangle waiting for the cooperative kernel.
struct QueuedTriangle {
    RasterVertex v[3];
    float shade, depth_scale;
};

struct HeightmapFrame {
    const DevicePatch* patches;
    LsrTransform screen;
    double camera_x, camera_y, camera_z, focal_px, near_m;
    float depth_scale, lod_quad_px, skirt_quads, ambient, level_gain;
    float sun[3];
    int fixed_step;
    float tint_rgb[3], tint_strength;
};

struct TriangleQueue {
    QueuedTriangle* items;
    unsigned int* count;
    unsigned int capacity;
};

void launch_patch_info(const HeightmapFrame& h, const Target& t, std::uint32_t patches, PatchInfo* info,
                       cudaStream_t stream);
void launch_patch_grids(const HeightmapFrame& h, const Target& t, const DeviceColours& c, const PatchInfo* info,
                        const PatchWork* work, std::uint32_t count, GridVertex* grid, unsigned char* drawn,
                        cudaStream_t stream);
void launch_patch_triangles(const HeightmapFrame& h, const Target& t, const DeviceColours& c, const PatchInfo* info,
                            const PatchWork* work, std::uint32_t count, const GridVertex* grid,
                            const unsigned char* drawn, TriangleQueue queue, cudaStream_t stream);
void launch_queued_triangles(const Target& t, TriangleQueue queue, int blocks, cudaStream_t stream);
// The heightmap pass's outline fill; `fills` holds a fragment per pixel (scratch).
void launch_fill_outline(const Target& t, Fragment* fills, cudaStream_t stream);
void launch_points(const Target& t, const DeviceColours& c, const DeviceBatch* batches, const PointJob* jobs,
                   std::uint64_t job_count, int point_size, int max_point_size, cudaStream_t stream);
void launch_resolve(const Target& t, const LsrResolve& r, std::uint32_t* image, float* log_depth,
                    unsigned long long* drawn, cudaStream_t stream);

}  // namespace lidarscout::render::cuda
