// Patch heightmaps: de-normalising a reconstruction into metres and rgba8, the linear method
// on a grid cell, and the footprint mask.
#include "viewer/patch_heightmap.hpp"

#include <algorithm>
#include <bitset>
#include <cmath>

#include "core/error.hpp"
#include "render/cache_key.hpp"
#include "render/framebuffer.hpp"

namespace lidarscout::viewer {
namespace {

std::uint8_t to_byte(float v) { return static_cast<std::uint8_t>(std::lround(std::clamp(v, 0.0f, 1.0f) * 255.0f)); }

// rgba8 per texel from a 3-channel image in [0, 1]; empty when the image has no colour at all.
std::vector<std::uint32_t> texture_of(const recon::Image& rgb) {
    if (rgb.channels != 3 || rgb.empty()) return {};
    const auto r = rgb.plane(0), g = rgb.plane(1), b = rgb.plane(2);
    const bool any = std::any_of(r.begin(), r.end(), [](float v) { return !std::isnan(v); });
    if (!any) return {};
    std::vector<std::uint32_t> out(rgb.texels());
    for (std::size_t t = 0; t < out.size(); ++t) {
        const bool defined = !std::isnan(r[t]) && !std::isnan(g[t]) && !std::isnan(b[t]);
        out[t] = defined ? render::pack_rgba(to_byte(r[t]), to_byte(g[t]), to_byte(b[t])) : kNoColourGrey;
    }
    return out;
}

bool overlaps(const dataset::Bounds& b, double min_x, double min_y, double max_x, double max_y) {
    return b.min_x <= max_x && b.max_x >= min_x && b.min_y <= max_y && b.max_y >= min_y;
}

bool inside_any(std::span<const dataset::Bounds> boxes, double x, double y) {
    return std::any_of(boxes.begin(), boxes.end(), [&](const dataset::Bounds& b) {
        return x >= b.min_x && x <= b.max_x && y >= b.min_y && y <= b.max_y;
    });
}

}  // namespace

Surface surface_of(const PointFilter& filter) {
    std::bitset<256> bare;
    bare.set(2), bare.set(9);
    if (filter.classes.none() || (filter.classes & ~bare).any()) return Surface::All;
    if (filter.keeps_class(2)) return filter.keeps_class(9) ? Surface::GroundAndWater : Surface::Ground;
    return Surface::Water;
}

const char* surface_name(Surface surface) {
    switch (surface) {
        case Surface::Ground: return "ground";
        case Surface::Water: return "water";
        case Surface::GroundAndWater: return "ground and water";
        case Surface::All: break;
    }
    return "every point";
}

render::HeightmapPatch PatchHeightmap::view(Surface wanted) const {
    render::PatchTint tint = render::PatchTint::None;
    if (surface != wanted) tint = render::PatchTint::All;
    else if (wanted != Surface::All && !colours.empty()) tint = render::PatchTint::Marked;
    return {origin_x, origin_y, texel_m, size, heights, colours, cache_key, tint};
}

std::shared_ptr<const PatchHeightmap> share(PatchHeightmap heightmap) {
    heightmap.cache_key = render::new_cache_key();
    return std::make_shared<const PatchHeightmap>(std::move(heightmap));
}

PatchHeightmap heightmap_from_reconstruction(lidarscout::CellKey cell, const recon::PatchPoints& points,
                                             const recon::Reconstruction& patch) {
    const recon::PatchSpec& spec = points.spec;
    if (patch.height.size != spec.patch_texels || patch.height.channels != 1) {
        throw Error::in_stage("viewer", "a heightmap needs a " + std::to_string(spec.patch_texels) + " x " +
                    std::to_string(spec.patch_texels) + " reconstruction, got " + std::to_string(patch.height.size));
    }
    PatchHeightmap h;
    h.cell = cell;
    h.origin_x = points.window_min_x + spec.pad_m();
    h.origin_y = points.window_min_y + spec.pad_m();
    h.texel_m = spec.texel_m;
    h.size = spec.patch_texels;
    h.heights.resize(patch.height.texels());
    for (std::size_t t = 0; t < h.heights.size(); ++t) {
        const float v = patch.height.values[t];
        h.heights[t] = std::isnan(v) ? recon::kNoValue : static_cast<float>(points.to_metres(v));
    }
    if (points.has_rgb && patch.rgb.size == spec.patch_texels) h.colours = texture_of(patch.rgb);
    return h;
}

std::optional<PatchHeightmap> linear_heightmap(const lidarscout::PatchGrid& grid, lidarscout::CellKey cell,
                                               const recon::PatchOptions& options) {
    const recon::PatchPoints points = recon::make_patch_points(grid, cell, options);
    if (points.status != recon::PatchStatus::Ok) return std::nullopt;
    recon::Reconstruction r = recon::reconstruct(points, recon::Method::Linear);
    const int n = options.spec.patch_texels;
    r.height = recon::crop_centre(r.height, n);
    r.rgb = recon::crop_centre(r.rgb, n);
    return heightmap_from_reconstruction(cell, points, r);
}

Footprints::Footprints(std::vector<dataset::Bounds> boxes)
    : shared_(std::make_shared<Shared>(dataset::TileIndex(std::span<const dataset::Bounds>(boxes)))) {}

std::vector<dataset::Bounds> Footprints::overlapping(double x0, double y0, double x1, double y1) const {
    std::vector<dataset::Bounds> near;
    if (!shared_) return near;
    const auto passes = [&](const dataset::Bounds& b) { return overlaps(b, x0, y0, x1, y1); };
    std::lock_guard lock(shared_->mutex);
    shared_->index.visit(passes, [&](std::uint32_t t) { near.push_back(shared_->index.bounds(t)); });
    return near;
}

bool mask_to_footprints(PatchHeightmap& h, const Footprints& footprints) {
    const double side = h.size * h.texel_m;
    const std::vector<dataset::Bounds> near =
        footprints.overlapping(h.origin_x, h.origin_y, h.origin_x + side, h.origin_y + side);
    bool any = false;
    for (int row = 0; row < h.size; ++row) {
        const double y = h.origin_y + (row + 0.5) * h.texel_m;
        for (int col = 0; col < h.size; ++col) {
            float& height = h.heights[static_cast<std::size_t>(row) * h.size + col];
            if (!inside_any(near, h.origin_x + (col + 0.5) * h.texel_m, y)) height = recon::kNoValue;
            any = any || !std::isnan(height);
        }
    }
    return any;
}

}  // namespace lidarscout::viewer
