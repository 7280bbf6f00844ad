// Algorithm 1: nearest and linear images from the patch geometry (see interpolation.hpp).
#include "recon/interpolation.hpp"

#include "core/error.hpp"
#include "recon/nearest.hpp"

namespace lidarscout::recon {
namespace {

void check_channels(const Image& image, const PointValues& values) {
    if (image.channels != values.channels) throw Error::in_stage("recon", "image and values differ in channels");
}

}  // namespace

PatchGeometry build_geometry(const PatchPoints& patch) {
    PatchGeometry g;
    g.triangulation = triangulate(patch);
    g.face_map = build_face_map(g.triangulation, patch.size());
    g.nearest = nearest_point_map(
        std::span<const GridXY>(g.triangulation.vertices.data(), g.triangulation.real_count), patch.size());
    return g;
}

void fill_nearest(Image& image, const std::vector<std::int32_t>& nearest, const PointValues& values,
                  const FaceMap* outside_of) {
    check_channels(image, values);
    for (int c = 0; c < values.channels; ++c) {
        const float* source = values.values.data() + c * values.count;
        auto plane = image.plane(c);
        for (std::size_t texel = 0; texel < nearest.size(); ++texel) {
            if (outside_of && outside_of->face[texel] >= 0) continue;
            plane[texel] = nearest[texel] >= 0 ? source[nearest[texel]] : kNoValue;
        }
    }
}

void fill_linear(Image& image, const Triangulation& triangulation, const FaceMap& map, const PointValues& values) {
    check_channels(image, values);
    for (int c = 0; c < values.channels; ++c) {
        const float* source = values.values.data() + c * values.count;
        auto plane = image.plane(c);
        for_each_inside_texel(map, [&](std::size_t texel, std::int32_t face, const std::array<float, 3>& w) {
            const auto& tri = triangulation.triangles[face];
            plane[texel] = w[0] * source[tri[0]] + w[1] * source[tri[1]] + w[2] * source[tri[2]];
        });
    }
}

Image nearest_image(const PatchGeometry& geometry, const PointValues& values) {
    Image image(geometry.face_map.size, values.channels);
    fill_nearest(image, geometry.nearest, values);
    return image;
}

Image linear_image(const PatchGeometry& geometry, const PointValues& values) {
    Image image(geometry.face_map.size, values.channels);
    fill_linear(image, geometry.triangulation, geometry.face_map, values);
    fill_nearest(image, geometry.nearest, values, &geometry.face_map);
    return image;
}

InterpolatedPatch interpolate_patch(const PatchPoints& patch) {
    InterpolatedPatch out;
    out.status = patch.status;
    if (patch.status != PatchStatus::Ok) return out;
    PatchGeometry geometry = build_geometry(patch);
    const PointValues heights = height_values(patch);
    out.height_nearest = nearest_image(geometry, heights);
    out.height_linear = linear_image(geometry, heights);
    if (patch.has_rgb) {
        const PointValues colours = colour_values(patch);
        out.rgb_nearest = nearest_image(geometry, colours);
        out.rgb_linear = linear_image(geometry, colours);
    } else {
        out.rgb_nearest = Image(patch.size(), 3);
        out.rgb_linear = Image(patch.size(), 3);
    }
    out.face_map = std::move(geometry.face_map);
    double sum = 0;
    for (const PatchPoint& p : patch.points) sum += p.h;
    out.mean_height = patch.points.empty() ? 0.0f : static_cast<float>(sum / static_cast<double>(patch.points.size()));
    return out;
}

}  // namespace lidarscout::recon
