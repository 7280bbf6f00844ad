/* The C interface between lidarscout and its CUDA rasterizer, liblidarscout_cuda_raster.so
 * (src/render/cuda/). The plugin is opened with dlopen by render/cuda_plugin.cpp, so that no
 * program links the CUDA runtime and a machine without the plugin or without a GPU simply
 * draws on the CPU. Everything the kernels need arrives prepared by the host side: camera
 * transforms already rebuilt per batch origin (double, then float), colour lookup tables from
 * the CPU Palette, normalised settings. Plain C types only; errors come back as text in the
 * caller's buffer. Bump LIDARSCOUT_CUDA_RASTER_ABI on any change. */
#ifndef LIDARSCOUT_RENDER_CUDA_RASTER_ABI_H
#define LIDARSCOUT_RENDER_CUDA_RASTER_ABI_H

#include <stddef.h>
#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

#define LIDARSCOUT_CUDA_RASTER_ABI 6

/* Offsets -> pixels and depth: w = depth . (p, 1), pixel = (sx . (p, 1), sy . (p, 1)) / w. */
typedef struct LsrTransform {
    float sx[4], sy[4], depth[4];
} LsrTransform;

/* The layout of render::PointAttr (20 bytes). */
typedef struct LsrPoint {
    float dx, dy, dz;
    uint8_t r, g, b, classification;
    uint16_t intensity;
    uint8_t returns; /* return kinds (core/point_filter.hpp), 0 when unknown */
    uint8_t padding;
} LsrPoint;

/* Which points are drawn (core/point_filter.hpp): all when `active` is 0; else a point whose
 * class bit is set in `classes`, whose return kinds meet `return_kinds` (or are unknown, 0) and
 * whose intensity lies in [intensity_min, intensity_max]. */
typedef struct LsrPointFilter {
    int active;
    uint32_t classes[8]; /* bit c % 32 of word c / 32: class c kept */
    uint32_t return_kinds;
    uint32_t intensity_min, intensity_max;
} LsrPointFilter;

typedef struct LsrBatch {
    const LsrPoint* points; /* host memory */
    uint64_t count;
    LsrTransform screen;    /* the camera transform for this batch's origin */
    float elevation_offset; /* elevation ramp index = (dz + elevation_offset) * ramp_scale */
    uint64_t key;           /* 0, or names these exact points: the plugin may keep them on the GPU */
    float size_scale;       /* > 0: a point's side is ceil(size_scale / depth) within the layer's sizes */
} LsrBatch;

typedef struct LsrPointLayer {
    const LsrBatch* batches;
    uint32_t batch_count;
    int point_size;     /* 1..64: the side of every point, or the smallest with a size_scale */
    int max_point_size; /* the largest side with a size_scale */
} LsrPointLayer;

typedef struct LsrPatch {
    double origin_x, origin_y; /* south-west corner, world metres */
    double texel_m;
    int size;                /* texels per side */
    const float* heights;    /* size x size, host memory, NaN = no data */
    const uint32_t* colours; /* size x size rgba8, or NULL */
    uint64_t key;            /* 0, or names these exact heights and colours: may be kept on the GPU */
    int tint;                /* LSR_TINT_*: which texels are mixed towards the tint colour */
} LsrPatch;

enum { LSR_TINT_NONE = 0, LSR_TINT_MARKED = 1 /* texels whose colour alpha < 255 */, LSR_TINT_ALL = 2 };

enum { LSR_COLOUR_RGB = 0, LSR_COLOUR_ELEVATION = 1, LSR_COLOUR_INTENSITY = 2, LSR_COLOUR_CLASSIFICATION = 3 };

typedef struct LsrColours {
    int mode;                 /* LSR_COLOUR_* */
    const uint32_t* ramp;     /* 1024 entries: the elevation ramp */
    float ramp_scale;
    float heightmap_offset;   /* the ramp offset for heights in world metres */
    const uint32_t* intensity; /* 65536 entries (one per intensity value) */
    const uint32_t* classes;   /* 256 entries */
    LsrPointFilter filter;     /* the points drawn */
} LsrColours;

typedef struct LsrHeightmapPass {
    const LsrPatch* patches;
    uint32_t patch_count;
    LsrTransform screen; /* camera-relative coordinates -> pixels */
    double camera_x, camera_y, camera_z, focal_px, near_m;
    float depth_scale;   /* 1 + depth bias */
    float lod_quad_px;
    int fixed_step;
    float skirt_quads;
    float sun[3];        /* normalised */
    float ambient;
    float level_gain;    /* scales the light so that level ground gets 1 */
    int fill_outline;    /* 1: empty pixels beside the drawn surface take their nearest drawn neighbour */
    float tint_rgb[3];   /* what tinted texels are mixed towards, 0..255 */
    float tint_strength; /* how far, 0..1 */
} LsrHeightmapPass;

typedef struct LsrResolve {
    uint32_t background;
    float edl_strength;
    int edl_radius_px;
} LsrResolve;

typedef struct LsrFrame {
    int width, height;
    float near_m, far_m;
    LsrColours colours;
    LsrHeightmapPass heightmaps;
    const LsrPointLayer* layers; /* drawn after the heightmaps, in order */
    uint32_t layer_count;
    uint32_t chunk_points; /* points per thread block */
    LsrResolve resolve;
} LsrFrame;

typedef struct LidarscoutCudaRasterApi {
    int abi; /* LIDARSCOUT_CUDA_RASTER_ABI */
    /* Opens the first GPU; NULL when there is none or it cannot be used (the cause in `error`). */
    void* (*open)(char* error, size_t error_size);
    /* The GPU's name, e.g. "NVIDIA H100 80GB HBM3". */
    const char* (*device_name)(void* context);
    /* Draws one frame into rgba (width x height, row 0 at the top) and counts the drawn pixels.
     * Returns 0 on success, else non-zero with the cause in `error`. One call at a time per
     * context. */
    int (*draw)(void* context, const LsrFrame* frame, uint32_t* rgba, uint64_t* drawn_pixels, char* error,
                size_t error_size);
    void (*close)(void* context);
} LidarscoutCudaRasterApi;

/* The one symbol the plugin exports. */
const LidarscoutCudaRasterApi* lidarscout_cuda_raster_api(void);

#ifdef __cplusplus
}
#endif

#endif
