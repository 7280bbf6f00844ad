// Orbit / pan / zoom / fly arithmetic of the viewer's camera.
#include "viewer/app/camera_controller.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "viewer/session_file.hpp"

namespace lidarscout::viewer::app {
namespace {

constexpr double kDegPerPixel = 0.25;
constexpr double kZoomPerStep = 0.85;
constexpr double kFrameCloser = 0.8;
constexpr double kMinDistance = session_range::kMinDistance, kMaxDistance = session_range::kMaxDistance;

}  // namespace

void CameraController::frame(const dataset::Bounds& box, int width, int height) {
    const render::Camera c = render::Camera::looking_at_bounds(box.min_x, box.min_y, box.min_z, box.max_x, box.max_y,
                                                               box.max_z, width, height, fov_deg);
    target_x = box.centre_x(), target_y = box.centre_y(), target_z = 0.5 * (box.min_z + box.max_z);
    // looking_at_bounds keeps every corner of the box in view; the terrain is a surface inside it,
    // so come closer until the near edge of the ground touches the bottom of the view.
    distance = std::clamp(kFrameCloser * std::hypot(c.x - target_x, c.y - target_y, c.z - target_z), kMinDistance,
                          kMaxDistance);
    yaw_deg = c.yaw_deg, pitch_deg = c.pitch_deg;
}

void CameraController::orbit(double dx_px, double dy_px) {
    yaw_deg = std::fmod(yaw_deg + dx_px * kDegPerPixel + 360.0, 360.0);
    pitch_deg = std::clamp(pitch_deg - dy_px * kDegPerPixel, session_range::kMinPitch, session_range::kMaxPitch);
}

void CameraController::pan(double dx_px, double dy_px, int height_px) {
    const render::Camera c = camera(height_px, height_px);
    const double metres_per_px = distance / c.focal_px();
    const auto b = c.basis();
    // Right drag: the ground under the cursor follows it (x along the view's right, y along the heading).
    const double fx = std::sin(yaw_deg * std::numbers::pi / 180), fy = std::cos(yaw_deg * std::numbers::pi / 180);
    target_x -= (b.right[0] * dx_px - fx * dy_px) * metres_per_px;
    target_y -= (b.right[1] * dx_px - fy * dy_px) * metres_per_px;
}

void CameraController::zoom(double wheel_steps) {
    distance = std::clamp(distance * std::pow(kZoomPerStep, wheel_steps), kMinDistance, kMaxDistance);
}

void CameraController::fly(const FlyKeys& k, double seconds) {
    const double speed = distance * (k.fast ? 2.0 : 0.6) * seconds;  // a view's depth in ~1.5 s
    const double yaw = yaw_deg * std::numbers::pi / 180;
    const double f = (k.forward ? 1.0 : 0.0) - (k.back ? 1.0 : 0.0), r = (k.right ? 1.0 : 0.0) - (k.left ? 1.0 : 0.0);
    target_x += speed * (f * std::sin(yaw) + r * std::cos(yaw));
    target_y += speed * (f * std::cos(yaw) - r * std::sin(yaw));
    target_z += speed * ((k.up ? 1.0 : 0.0) - (k.down ? 1.0 : 0.0));
}

render::Camera CameraController::camera(int width, int height) const {
    render::Camera c;
    c.width = std::max(1, width), c.height = std::max(1, height);
    c.fov_deg = fov_deg;
    c.yaw_deg = yaw_deg, c.pitch_deg = pitch_deg;
    const auto f = c.basis().forward;
    c.x = target_x - distance * f[0], c.y = target_y - distance * f[1], c.z = target_z - distance * f[2];
    c.near_m = std::max(0.1, distance * 1e-3);
    c.far_m = std::max(1e4, distance * 1e3);
    return c;
}

}  // namespace lidarscout::viewer::app
