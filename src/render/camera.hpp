// The viewer's camera: a position in world metres (x east, y north, z up), a heading (yaw), a
// pitch and a vertical field of view, and the transforms the rasterizers use to take points
// to pixels. World coordinates are ~1e6 m, too large for float: every transform subtracts the
// camera position (or a batch origin minus the camera position) in double first and only then
// goes to float.
//
// Screen conventions shared by all passes: pixel (i, j) covers [i, i + 1) x [j, j + 1), row 0
// is the top of the image, and the depth of a point is its distance along the viewing
// direction in metres (positive in front of the camera).
#pragma once

#include <array>
#include <optional>
#include <string_view>

namespace lidarscout::render {

// Row-major 4x4 matrix in float, applied to column vectors (x, y, z, 1).
struct Mat4 {
    std::array<float, 16> m{};
    float operator()(int row, int col) const { return m[row * 4 + col]; }
    float& operator()(int row, int col) { return m[row * 4 + col]; }
};

// Maps coordinates relative to some origin to the screen: for p = (x, y, z),
//   w = dot(depth, p) + depth_offset            (view depth in metres)
//   pixel x = (dot(sx, p) + sx_offset) / w,  pixel y = (dot(sy, p) + sy_offset) / w.
// Each of the three rows is a linear function of p, so `row(p) >= 0` is a half-space: the
// frustum tests use this (see in_frustum_planes in point_pass / heightmap_pass).
struct ScreenTransform {
    std::array<float, 4> sx{}, sy{}, depth{};
};

struct ScreenPoint {
    float x = 0, y = 0;  // pixel coordinates (continuous; pixel index = floor)
    float depth = 0;     // metres along the viewing direction
};

struct ViewBasis {
    std::array<double, 3> forward{}, right{}, up{};  // unit vectors, world frame
};

struct Camera {
    double x = 0, y = 0, z = 0;  // position, world metres
    double yaw_deg = 0;          // heading: 0 = looking north (+y), 90 = east (+x)
    double pitch_deg = 0;        // negative = looking down; within [-90, 90]
    double fov_deg = 60;         // vertical field of view
    int width = 1280, height = 720;
    double near_m = 0.1, far_m = 1e7;  // depths outside [near, far] are not drawn

    bool operator==(const Camera&) const = default;

    ViewBasis basis() const;
    // Pixels per unit of (lateral offset / depth): the focal length in pixels.
    double focal_px() const;

    // The classic clip-space matrix for world coordinates relative to the camera position
    // (world - camera, computed in double by the caller): clip x, y in [-w, w] on screen
    // (y up), clip z in [-w, w] between near and far (OpenGL convention), clip w = depth.
    Mat4 view_projection() const;
    // The rasterizers' form: coordinates relative to `origin` straight to pixels and depth.
    // origin - camera is taken in double, then the whole transform goes to float.
    ScreenTransform screen_transform(double origin_x, double origin_y, double origin_z) const;

    // The pixel position and depth of a world point; nullopt when it is nearer than near_m
    // (or behind the camera) or farther than far_m. Points outside the image are returned.
    std::optional<ScreenPoint> project(double px, double py, double pz) const;

    // The "auto" camera: seen from the south, looking north and down at 60 degrees, aimed at
    // the box centre, as close as it can be with the whole box within 95% of the image;
    // near/far chosen to hold the box.
    static Camera looking_at_bounds(double min_x, double min_y, double min_z, double max_x, double max_y,
                                    double max_z, int width, int height, double fov_deg = 60);
};

// "X,Y,Z,YAW,PITCH" (metres, degrees) -> a camera of the given size and field of view.
// Throws lidarscout::Error on a wrong field count, text that is not a finite number, or a
// pitch outside [-90, 90].
Camera parse_camera(std::string_view text, int width = 1280, int height = 720, double fov_deg = 60);

}  // namespace lidarscout::render
