// The heightmap pass: draws heightmap patches (a grid of heights and colours per patch) as
// shaded, textured triangle meshes into the framebuffer, pushed back by a small depth bias so
// that real points lying on the surface win the atomic min.
//
// Mesh layout (our choice, so that adjacent patches join without gaps): vertices sit at the
// texel *corners*, (size + 1) x (size + 1) of them, and texel (row j, column i) is the quad
// between corners (i, j) and (i + 1, j + 1). The outer corners lie exactly on the patch
// boundary, computed from the patch origin in double, so two patches whose edges abut produce
// bit-identical screen positions along the shared edge, and the rasterizer's top-left rule
// then covers every pixel there exactly once. A corner's colour is the mean of the (up to 4)
// defined texels around it inside the patch, and so is its height inside the patch; on the
// boundary the height is extrapolated linearly from the nearest 2 x 2 texel centres, so that
// the two patches of a seam agree up to the terrain's curvature (each patch only sees its own
// texels). A texel whose height is NaN is not drawn (a hole of exactly that texel at full
// detail).
//
// Level of detail: from the patch's distance to the camera, a step (1, 2, 4, ... up to the
// patch size) is chosen so that a quad of step x step texels stays about lod_quad_px pixels on
// screen; at step s only every s-th corner is used and a block of s x s texels is drawn whole
// when all its texels are defined. A block with some undefined texels (a patch on the edge of
// the data) is split in four, down to blocks of about a pixel, drawn when at least half defined,
// so that the defined area is drawn at every distance (a coarse block is not dropped for one
// missing texel). Neighbours drawn at different steps, or whose boundary heights
// differ, can leave thin slits when seen from the side: each patch therefore hangs a "skirt"
// (a vertical strip, skirt_quads x step x texel deep, shaded like the surface above it) down
// from its boundary, hidden under the neighbour where there is one.
//
// Colour: ColourMode::Elevation colours by height (the same ramp as the points); every other
// mode uses the patch texture (grey where the patch has none). Shading: Lambert from the face
// normal with a fixed sun direction, plus ambient, scaled so that level ground shows the
// texture's own colour (the colour of the points it stands for).
//
// Tint: a patch that stands in for a surface it does not show (the viewer's overview heightmap
// while a ground filter asks for bare earth) is drawn mixed towards tint_rgb by tint_strength:
// PatchTint::All tints the whole patch, PatchTint::Marked the texels whose colour's alpha is below
// 255 (the others show the filtered surface). A corner takes the share of tinted texels around it.
//
// Outline: a pixel the surface's edge crosses without covering its centre would stay empty,
// where the points it stands for light it (a point lights the pixel it falls in). Seen from
// afar, where a tile is a few pixels wide, that empty outline is a large share of the picture:
// with fill_outline, after the patches are drawn, each empty pixel beside a drawn one takes its
// nearest drawn neighbour (one pixel, not spreading).
//
// Triangles with a vertex nearer than the camera's near plane are dropped (not clipped).
// Patches are spread over the thread pool.
#pragma once

#include <array>
#include <cstdint>
#include <span>

#include "core/thread_pool.hpp"
#include "render/camera.hpp"
#include "render/colour_modes.hpp"
#include "render/framebuffer.hpp"

namespace lidarscout::render {

enum class PatchTint : std::uint8_t { None, Marked, All };

struct HeightmapPatch {
    double origin_x = 0, origin_y = 0;  // south-west (min x, min y) corner, world metres
    double texel_m = 10;                // texel side, metres
    int size = 64;                      // texels per side
    // size x size, row-major, row 0 = south (min y), column 0 = west (min x), as recon's
    // patch images. Heights in world metres, NaN = no data; colours rgba8 (see
    // framebuffer.hpp), or empty for an untextured patch.
    std::span<const float> heights;
    std::span<const std::uint32_t> colours;
    std::uint64_t cache_key = 0;  // 0, or new_cache_key() (cache_key.hpp): kept on the GPU
    PatchTint tint = PatchTint::None;  // Marked needs colours (their alpha marks the tinted texels)
};

struct HeightmapPassSettings {
    ColourSettings colour;
    float depth_bias = 0.002f;  // surface depth is multiplied by 1 + depth_bias
    float lod_quad_px = 3.0f;   // target size of a LOD quad on screen, pixels
    int fixed_step = 0;         // > 0: this step for every patch instead of the LOD choice
    float skirt_quads = 1.0f;   // skirt depth in quads (step x texel); 0 = no skirts
    std::array<float, 3> sun = {-0.5f, 0.5f, 0.7071f};  // towards the sun (north-west, 45 deg up)
    float ambient = 0.35f;      // light where the sun does not reach
    bool fill_outline = true;   // empty pixels beside the drawn surface take their nearest drawn neighbour
    std::array<float, 3> tint_rgb = {200.0f, 60.0f, 200.0f};  // what tinted texels are mixed towards (0..255)
    float tint_strength = 0.55f;  // how far: 0 = not at all, 1 = the tint colour alone
};

// What the light is scaled by so that level ground gets 1 (its texture's own colour), for a
// normalised sun whose height is sun_z: 1 / (ambient + (1 - ambient) * max(0, sun_z)); 1 when that is 0.
float level_gain(float sun_z, float ambient);

// The LOD step for a patch whose heights span [z_min, z_max]: the largest power of two
// (at most the patch size) whose quads stay within lod_quad_px on screen at the patch's
// nearest point to the camera.
int lod_step(const HeightmapPatch& patch, double z_min, double z_max, const Camera& camera, float lod_quad_px);

// Draws the patches into `fb` (whose size must be the camera's). Throws lidarscout::Error on
// a size mismatch, a patch whose spans do not hold size x size values, or bad settings.
void draw_heightmaps(Framebuffer& fb, const Camera& camera, std::span<const HeightmapPatch> patches,
                     const HeightmapPassSettings& settings, ThreadPool& pool);

}  // namespace lidarscout::render
