// The viewer's cursor readout: the point of the ground under a pixel — where the ray through
// the pixel meets the horizontal plane at a given height (the orbit target's) — in the
// dataset's metres and, where the dataset's CRS is known, in longitude and latitude (PROJ).
#pragma once

#include <array>
#include <memory>
#include <optional>
#include <string>

#include "dataset/dataset.hpp"
#include "render/camera.hpp"

namespace lidarscout::geo {
class CrsTransform;
}

namespace lidarscout::viewer {

// The direction of the ray through pixel (px, py), scaled so that its component along the
// viewing direction is 1: camera position + t * ray is the point at depth t metres.
std::array<double, 3> pixel_ray(const render::Camera& camera, double px, double py);

// (x, y) in world metres; nullopt when the ray does not meet the plane in front of the camera.
std::optional<std::array<double, 2>> ground_under_pixel(const render::Camera& camera, double px, double py,
                                                        double ground_z);

class CursorReadout {
public:
    // Never throws: a frame without a CRS, or one PROJ does not know, gives no lon/lat.
    explicit CursorReadout(const dataset::Frame& frame);
    ~CursorReadout();

    bool has_lonlat() const { return transform_ != nullptr; }
    // {longitude, latitude} in degrees (WGS 84) of a point in the frame's metres.
    std::optional<std::array<double, 2>> lonlat(double x_m, double y_m) const;
    // "x 612345.6 m, y 4123456.7 m  lon -83.123456, lat 37.654321" (no lon/lat without a CRS);
    // "" when the pixel shows sky.
    std::string text(const render::Camera& camera, double px, double py, double ground_z) const;

private:
    std::unique_ptr<geo::CrsTransform> transform_;
    double xy_to_metres_ = 1.0;
};

}  // namespace lidarscout::viewer
