// The viewer's camera controls, without any window code: an orbit camera around a target
// point (orbit = left drag, pan = right drag, zoom = wheel, WASD/QE = fly the target along the
// heading), framing of a box (the start view, double-click on a tile), and the render::Camera
// it gives for a viewport, with near/far planes that follow the distance.
#pragma once

#include "dataset/dataset.hpp"
#include "render/camera.hpp"

namespace lidarscout::viewer::app {

// Keys held this frame (WASD: forward/left/back/right, Q/E: down/up, shift: faster).
struct FlyKeys {
    bool forward = false, back = false, left = false, right = false, up = false, down = false, fast = false;
};

class CameraController {
public:
    double target_x = 0, target_y = 0, target_z = 0;  // the point orbited, world metres
    double distance = 1000;                             // from the camera to the target, metres
    double yaw_deg = 0, pitch_deg = -60;                 // as render::Camera
    double fov_deg = 60;

    // Looks at `box` from the south, 60 degrees down, its ground filling a width x height view.
    void frame(const dataset::Bounds& box, int width, int height);

    void orbit(double dx_px, double dy_px);                // mouse motion while orbiting
    void pan(double dx_px, double dy_px, int height_px);   // moves the target with the cursor
    void zoom(double wheel_steps);                         // > 0 comes closer
    void fly(const FlyKeys& keys, double seconds);         // moves the target along the heading

    render::Camera camera(int width, int height) const;

    bool operator==(const CameraController&) const = default;  // (tells whether the user moved it)
};

}  // namespace lidarscout::viewer::app
