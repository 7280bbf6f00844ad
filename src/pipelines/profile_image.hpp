// A profile drawn as an image: distance along the line (left to right) against height (bottom to
// top), each point a dot in its ASPRS class colour (or on an elevation ramp), the classes drawn in a
// fixed order so that ground lies on top (profile_draw_rank), over grid lines at round steps of the
// CRS's units. The image a user gets (`profile -o x.png`, the viewer's export) is at true scale by
// default (a unit of height as long as a unit of distance, or `exaggeration` times longer) and has
// labelled axes: the tick values, and the axes' titles with their units, in our bitmap font
// (render/bitmap_font.hpp). The viewer's own panel draws a fixed size, the heights filling it, and
// says what the axes span below it.
#pragma once

#include <cmath>
#include <cstdint>
#include <string>

#include "pipelines/profile.hpp"
#include "render/resolve.hpp"

namespace lidarscout::dataset {
struct Frame;
}

namespace lidarscout::pipelines {

struct ProfileImageScale {
    double z_min = 0, z_max = 0;  // heights at the plot's bottom and top edges
    double distance_step = 0, z_step = 0;  // the grid lines' spacing
    double px_per_distance = 0, px_per_z = 0;  // the plot's scales, pixels per CRS unit
    // The heights' scale over the distances', both in metres: 1 at true scale.
    double exaggeration = 0;
};

enum class ProfileColours { Classification, Elevation };

struct ProfileImageOptions {
    int width = 1600;  // the image's width; narrower when the heights would be too tall for it
    // 0: as tall as the heights need at `exaggeration` (within limits: a flat profile gets room for its
    // labels, a steep one a narrower plot); else this height, the heights filling it.
    int height = 0;
    double exaggeration = 1;  // with height 0: the vertical scale over the horizontal (1: true scale)
    double z_to_metres = 1, distance_to_metres = 1;  // the units' lengths (their ratio sets the scale)
    std::string distance_unit, z_unit;  // "m", "US ft", ...: the axes' titles ("units" when empty)
    bool labels = true;  // tick values and titles (in the margins); false: the bare plot
    ProfileColours colours = ProfileColours::Classification;
    // The elevation ramp spans ramp_min - ramp_max (the frame CRS's units, e.g. the whole dataset's
    // heights, as the viewer colours its points), or the plot's heights when they are NaN.
    double ramp_min = NAN, ramp_max = NAN;
};

// The options of the image a user gets for a dataset in `frame`: true scale, the axes labelled in
// its units.
ProfileImageOptions profile_png_options(const dataset::Frame& frame, double exaggeration = 1);

// The order classes are drawn in, lowest first (so the last drawn shows where points overlap):
// noise, high, medium and low vegetation, never classified and unclassified, the other classes,
// buildings, water, ground on top.
int profile_draw_rank(std::uint8_t classification);

// The image; `scale` (when given) receives what the axes span. Throws lidarscout::Error for an
// exaggeration that is not a positive number.
render::RgbaImage profile_image(const Profile& profile, const Corridor& corridor, const ProfileImageOptions& options,
                                ProfileImageScale* scale = nullptr);

// The viewer's panel: width x height pixels, the heights filling them, no labels.
render::RgbaImage profile_image(const Profile& profile, const Corridor& corridor, int width, int height,
                                ProfileImageScale* scale = nullptr,
                                ProfileColours colours = ProfileColours::Classification, double ramp_min = NAN,
                                double ramp_max = NAN);

}  // namespace lidarscout::pipelines
