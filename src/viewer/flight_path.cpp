// The scripted flight used by the memory-budget test and bench_view.
#include "viewer/flight_path.hpp"

#include <algorithm>

namespace lidarscout::viewer {

render::Camera flight_camera(const dataset::Bounds& b, double t, const FlightPath& path) {
    t = std::clamp(t, 0.0, 1.0);
    render::Camera c;
    c.width = path.width, c.height = path.height;
    c.x = b.min_x + (0.2 + 0.6 * t) * (b.max_x - b.min_x);
    c.y = b.min_y + (0.2 + 0.6 * t) * (b.max_y - b.min_y);
    c.z = b.max_z + path.start_height_m + t * (path.end_height_m - path.start_height_m);
    c.yaw_deg = path.yaw_deg;
    c.pitch_deg = path.pitch_deg;
    c.near_m = 1, c.far_m = 1e6;
    return c;
}

}  // namespace lidarscout::viewer
