// Camera transforms (double until the camera position is subtracted) and camera parsing.
#include "render/camera.hpp"

#include <algorithm>
#include <charconv>
#include <limits>
#include <cmath>
#include <numbers>
#include <string>
#include <vector>

#include "core/error.hpp"

namespace lidarscout::render {
namespace {

constexpr double kDegToRad = std::numbers::pi / 180.0;
constexpr double kAutoPitchDeg = -60.0;

using Vec3 = std::array<double, 3>;

double dot(const Vec3& a, const Vec3& b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }

Vec3 cross(const Vec3& a, const Vec3& b) {
    return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
}

// A row of a ScreenTransform: coefficients `v` and offset `dot(v, t) + extra` in float.
std::array<float, 4> make_row(const Vec3& v, const Vec3& t, double extra = 0.0) {
    return {static_cast<float>(v[0]), static_cast<float>(v[1]), static_cast<float>(v[2]),
            static_cast<float>(dot(v, t) + extra)};
}

Vec3 scaled_sum(double a, const Vec3& u, double b, const Vec3& v) {
    return {a * u[0] + b * v[0], a * u[1] + b * v[1], a * u[2] + b * v[2]};
}

double parse_number(std::string_view field, std::string_view text) {
    while (!field.empty() && field.front() == ' ') field.remove_prefix(1);
    while (!field.empty() && field.back() == ' ') field.remove_suffix(1);
    double value = 0;
    const auto [end, ec] = std::from_chars(field.data(), field.data() + field.size(), value);
    if (field.empty() || ec != std::errc() || end != field.data() + field.size() || !std::isfinite(value)) {
        throw Error("camera '" + std::string(text) + "': '" + std::string(field) + "' is not a number");
    }
    return value;
}

std::vector<std::string_view> split_commas(std::string_view text) {
    std::vector<std::string_view> fields;
    for (std::size_t start = 0;;) {
        const std::size_t comma = text.find(',', start);
        fields.push_back(text.substr(start, comma == std::string_view::npos ? std::string_view::npos : comma - start));
        if (comma == std::string_view::npos) return fields;
        start = comma + 1;
    }
}

// Whether all 8 corners of the box lie within `fill` of the image (by NDC) when the camera
// looks at `centre` from `distance` along its viewing direction.
bool box_fits(const Camera& cam, const Vec3& lo, const Vec3& hi, const Vec3& centre, double distance, double fill) {
    const ViewBasis b = cam.basis();
    const double t = std::tan(0.5 * cam.fov_deg * kDegToRad), aspect = static_cast<double>(cam.width) / cam.height;
    for (int corner = 0; corner < 8; ++corner) {
        const Vec3 p = {(corner & 1) ? hi[0] : lo[0], (corner & 2) ? hi[1] : lo[1], (corner & 4) ? hi[2] : lo[2]};
        const Vec3 v = {p[0] - centre[0], p[1] - centre[1], p[2] - centre[2]};
        const double depth = distance + dot(v, b.forward);
        if (depth <= 0.0) return false;
        if (std::abs(dot(v, b.right)) > fill * depth * t * aspect || std::abs(dot(v, b.up)) > fill * depth * t) {
            return false;
        }
    }
    return true;
}

// The smallest distance from the box centre at which the box fills at most 95% of the image
// (bisection: moving along the viewing direction only scales the projection, so the fit is
// monotonic). The bounding sphere's distance always fits.
double fitting_distance(const Camera& cam, const Vec3& lo, const Vec3& hi, const Vec3& centre, double radius) {
    constexpr double kFill = 0.95;
    const double half_v = 0.5 * cam.fov_deg * kDegToRad;
    const double half_h = std::atan(std::tan(half_v) * cam.width / std::max(1, cam.height));
    double far = radius / std::sin(std::min(half_v, half_h)) / kFill, near = 0.0;
    for (int i = 0; i < 60; ++i) {
        const double mid = 0.5 * (near + far);
        (box_fits(cam, lo, hi, centre, mid, kFill) ? far : near) = mid;
    }
    return far;
}

}  // namespace

// A pass asks one camera for its basis and focal length for every box and point it looks at (the
// footprints and visibility of 152,100 tiles: sin, cos and tan were half of a frame's work), so each
// thread keeps the last ones it made, keyed by the angles and height they came from.
ViewBasis Camera::basis() const {
    thread_local double made_yaw = std::numeric_limits<double>::quiet_NaN(), made_pitch = made_yaw;
    thread_local ViewBasis made;
    if (yaw_deg == made_yaw && pitch_deg == made_pitch) return made;
    const double yaw = yaw_deg * kDegToRad, pitch = pitch_deg * kDegToRad;
    ViewBasis b;
    b.forward = {std::sin(yaw) * std::cos(pitch), std::cos(yaw) * std::cos(pitch), std::sin(pitch)};
    b.right = {std::cos(yaw), -std::sin(yaw), 0.0};
    b.up = cross(b.right, b.forward);
    made_yaw = yaw_deg, made_pitch = pitch_deg, made = b;
    return b;
}

double Camera::focal_px() const {
    thread_local double made_fov = std::numeric_limits<double>::quiet_NaN();
    thread_local int made_height = 0;
    thread_local double made = 0;
    if (fov_deg != made_fov || height != made_height) {
        made = 0.5 * height / std::tan(0.5 * fov_deg * kDegToRad);
        made_fov = fov_deg, made_height = height;
    }
    return made;
}

Mat4 Camera::view_projection() const {
    const ViewBasis b = basis();
    const double t = std::tan(0.5 * fov_deg * kDegToRad);
    const double aspect = static_cast<double>(width) / height;
    const double n = near_m, f = far_m;
    Mat4 m;
    for (int c = 0; c < 3; ++c) {
        m(0, c) = static_cast<float>(b.right[c] / (t * aspect));
        m(1, c) = static_cast<float>(b.up[c] / t);
        m(2, c) = static_cast<float>(b.forward[c] * (f + n) / (f - n));
        m(3, c) = static_cast<float>(b.forward[c]);
    }
    m(2, 3) = static_cast<float>(-2.0 * f * n / (f - n));
    return m;
}

ScreenTransform Camera::screen_transform(double origin_x, double origin_y, double origin_z) const {
    const ViewBasis b = basis();
    const Vec3 t = {origin_x - x, origin_y - y, origin_z - z};
    const double f = focal_px(), cx = 0.5 * width, cy = 0.5 * height;
    ScreenTransform s;
    // pixel x = cx + f * right.p / depth; pixel y = cy - f * up.p / depth (rows grow downwards).
    s.sx = make_row(scaled_sum(f, b.right, cx, b.forward), t);
    s.sy = make_row(scaled_sum(-f, b.up, cy, b.forward), t);
    s.depth = make_row(b.forward, t);
    return s;
}

std::optional<ScreenPoint> Camera::project(double px, double py, double pz) const {
    const ViewBasis b = basis();
    const Vec3 v = {px - x, py - y, pz - z};
    const double depth = dot(v, b.forward);
    if (!(depth >= near_m && depth <= far_m)) return std::nullopt;
    const double f = focal_px();
    return ScreenPoint{static_cast<float>(0.5 * width + f * dot(v, b.right) / depth),
                       static_cast<float>(0.5 * height - f * dot(v, b.up) / depth), static_cast<float>(depth)};
}

Camera Camera::looking_at_bounds(double min_x, double min_y, double min_z, double max_x, double max_y, double max_z,
                                 int width, int height, double fov_deg) {
    Camera cam;
    cam.width = width;
    cam.height = height;
    cam.fov_deg = fov_deg;
    cam.yaw_deg = 0;
    cam.pitch_deg = kAutoPitchDeg;
    const Vec3 lo = {min_x, min_y, min_z}, hi = {max_x, max_y, max_z};
    const Vec3 centre = {0.5 * (min_x + max_x), 0.5 * (min_y + max_y), 0.5 * (min_z + max_z)};
    const double radius = std::max(1.0, 0.5 * std::hypot(max_x - min_x, max_y - min_y, max_z - min_z));
    const double distance = fitting_distance(cam, lo, hi, centre, radius);
    const Vec3 forward = cam.basis().forward;
    cam.x = centre[0] - distance * forward[0];
    cam.y = centre[1] - distance * forward[1];
    cam.z = centre[2] - distance * forward[2];
    cam.near_m = std::max(0.1, 0.01 * (distance - radius));
    cam.far_m = 2.0 * (distance + radius);
    return cam;
}

Camera parse_camera(std::string_view text, int width, int height, double fov_deg) {
    const std::vector<std::string_view> fields = split_commas(text);
    if (fields.size() != 5) {
        throw Error("camera '" + std::string(text) + "': expected X,Y,Z,YAW,PITCH (5 numbers), got " +
                    std::to_string(fields.size()) + " fields");
    }
    Camera cam;
    cam.x = parse_number(fields[0], text);
    cam.y = parse_number(fields[1], text);
    cam.z = parse_number(fields[2], text);
    cam.yaw_deg = parse_number(fields[3], text);
    cam.pitch_deg = parse_number(fields[4], text);
    if (cam.pitch_deg < -90.0 || cam.pitch_deg > 90.0) {
        throw Error("camera '" + std::string(text) + "': pitch must be within [-90, 90] degrees");
    }
    cam.width = width;
    cam.height = height;
    cam.fov_deg = fov_deg;
    return cam;
}

}  // namespace lidarscout::render
