// ground_under_pixel (the inverse of Camera::project on a plane) and the lon/lat readout.
#include "viewer/cursor_readout.hpp"

#include <cmath>
#include <cstdio>

#include "core/error.hpp"
#include "geo/projection.hpp"

namespace lidarscout::viewer {

std::array<double, 3> pixel_ray(const render::Camera& camera, double px, double py) {
    const render::ViewBasis b = camera.basis();
    const double f = camera.focal_px();
    const double a = (px - 0.5 * camera.width) / f, c = (0.5 * camera.height - py) / f;
    std::array<double, 3> ray{};
    for (int i = 0; i < 3; ++i) ray[i] = b.forward[i] + a * b.right[i] + c * b.up[i];
    return ray;
}

std::optional<std::array<double, 2>> ground_under_pixel(const render::Camera& camera, double px, double py,
                                                        double ground_z) {
    const auto ray = pixel_ray(camera, px, py);
    if (std::abs(ray[2]) < 1e-12) return std::nullopt;
    const double t = (ground_z - camera.z) / ray[2];
    if (!(t > 0)) return std::nullopt;
    return std::array<double, 2>{camera.x + t * ray[0], camera.y + t * ray[1]};
}

CursorReadout::CursorReadout(const dataset::Frame& frame) : xy_to_metres_(frame.xy_to_metres) {
    if (frame.crs.empty()) return;
    try {
        transform_ = std::make_unique<geo::CrsTransform>(frame.crs, "EPSG:4326");
    } catch (const Error&) {
        transform_.reset();  // the readout then shows metres only
    }
}

CursorReadout::~CursorReadout() = default;

std::optional<std::array<double, 2>> CursorReadout::lonlat(double x_m, double y_m) const {
    if (!transform_) return std::nullopt;
    double x = x_m / xy_to_metres_, y = y_m / xy_to_metres_, z = 0;
    try {
        transform_->apply(x, y, z);
    } catch (const Error&) {
        return std::nullopt;  // outside the CRS's area
    }
    return std::array<double, 2>{x, y};
}

std::string CursorReadout::text(const render::Camera& camera, double px, double py, double ground_z) const {
    const auto ground = ground_under_pixel(camera, px, py, ground_z);
    if (!ground) return "";
    char buffer[160];
    int n = std::snprintf(buffer, sizeof buffer, "x %.1f m, y %.1f m", (*ground)[0], (*ground)[1]);
    if (const auto ll = lonlat((*ground)[0], (*ground)[1])) {
        std::snprintf(buffer + n, sizeof buffer - n, "  lon %.6f, lat %.6f", (*ll)[0], (*ll)[1]);
    }
    return buffer;
}

}  // namespace lidarscout::viewer
