// A scripted camera flight over a dataset, the same for the memory-budget test and the
// viewer benchmark: from high above the whole dataset down to low altitude along its
// diagonal, looking ahead (north-east) and down.
#pragma once

#include "dataset/dataset.hpp"
#include "render/camera.hpp"

namespace lidarscout::viewer {

struct FlightPath {
    double start_height_m = 20000;  // above the dataset's top at t = 0
    double end_height_m = 200;      // above the dataset's top at t = 1
    double yaw_deg = 45;            // the direction of travel
    double pitch_deg = -60;
    int width = 1280, height = 720;
};

// The camera at t in [0, 1] (clamped): x, y go from 20% to 80% of the bounds' diagonal while
// the height falls linearly.
render::Camera flight_camera(const dataset::Bounds& bounds_m, double t, const FlightPath& path = {});

}  // namespace lidarscout::viewer
