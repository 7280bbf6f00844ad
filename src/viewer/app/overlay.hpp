// Lines drawn over a resolved image after the scene: the tiles' outlines on the ground (the
// "tile boxes" layer, and the footprints of the tiles read while a dataset opens), the selected
// tile highlighted; the picked point, the measured line, the area tool's polygon and a profile's
// corridor.
#pragma once

#include <cstdint>
#include <array>
#include <optional>
#include <span>

#include "dataset/dataset.hpp"
#include "dataset/tile_index.hpp"
#include "render/camera.hpp"
#include "render/resolve.hpp"
#include "viewer/picking.hpp"

namespace lidarscout::viewer::app {

// Draws a world-space segment (skipped where an end is behind the near plane).
void draw_segment(render::RgbaImage& image, const render::Camera& camera, double x0, double y0, double z0, double x1,
                  double y1, double z1, std::uint32_t rgba);

// The xy outline of every tile in view (at its bounds' lowest height; found through `places`), in
// `rgba`; `selected` in white.
void draw_tile_boxes(render::RgbaImage& image, const render::Camera& camera, const dataset::Dataset& dataset,
                     const dataset::TileIndex& places, std::uint32_t rgba, std::optional<std::uint32_t> selected);

// The xy outline of each box (at its lowest height): the tiles read so far while a dataset opens.
void draw_footprints(render::RgbaImage& image, const render::Camera& camera, std::span<const dataset::Bounds> boxes,
                     std::uint32_t rgba);

// A small cross centred on the projection of a world point.
void draw_marker(render::RgbaImage& image, const render::Camera& camera, double x, double y, double z,
                 std::uint32_t rgba);

// The click tool's points as markers, and the line between the two measured points.
void draw_click_overlay(render::RgbaImage& image, const render::Camera& camera, const ClickState& click);

// A profile's corridor from line[0..1] to line[2..3] (world metres), its centre line and its two
// sides half_width away, over the ground: heights (world metres) of equal pieces of the line, or
// `z` all along when there are none.
void draw_corridor(render::RgbaImage& image, const render::Camera& camera, const std::array<double, 4>& line,
                   double half_width, std::span<const double> heights, double z, std::uint32_t rgba);

}  // namespace lidarscout::viewer::app
