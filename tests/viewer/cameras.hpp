// Cameras the viewer tests share.
#pragma once

#include "render/camera.hpp"

namespace lidarscout::test {

// Straight down onto (x, y) from `height` metres above z = 0 (north at the top of the image).
inline render::Camera looking_down(double x, double y, double height) {
    render::Camera c;
    c.x = x, c.y = y, c.z = height;
    c.pitch_deg = -90;
    c.near_m = 0.5, c.far_m = 1e5;
    return c;
}

}  // namespace lidarscout::test
