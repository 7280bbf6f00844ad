// A profile drawn as an image: distance along the line (left to right) against height (bottom to
// top), each on its own scale (heights exaggerated to fill the image), each point a dot in its ASPRS
// class colour (or on an elevation ramp), over grid lines at round steps of
// the CRS's units (their spacing is given back: the image has no text).
#pragma once

#include <cmath>

#include "pipelines/profile.hpp"
#include "render/resolve.hpp"

namespace lidarscout::pipelines {

struct ProfileImageScale {
    double z_min = 0, z_max = 0;  // heights at the plot's bottom and top edges
    double distance_step = 0, z_step = 0;  // the grid lines' spacing
};

enum class ProfileColours { Classification, Elevation };

// An image of width x height pixels, the plot inset by a margin; `scale` (when given) receives what
// the axes span. The elevation ramp spans ramp_min - ramp_max (the frame CRS's units, e.g. the whole
// dataset's heights, as the viewer colours its points), or the plot's heights when they are NaN.
render::RgbaImage profile_image(const Profile& profile, const Corridor& corridor, int width = 1600, int height = 600,
                                ProfileImageScale* scale = nullptr,
                                ProfileColours colours = ProfileColours::Classification, double ramp_min = NAN,
                                double ramp_max = NAN);

}  // namespace lidarscout::pipelines
