// The viewer's area tool without window code: the polygon clicked on the ground measured on the
// full-resolution points the viewer holds (every level of the LOD blocks it overlaps, only those
// the filter keeps): its area, surface, and the volume above and below the plane through its
// vertices (recon/area_volume.hpp).
#pragma once

#include <span>
#include <string>

#include "core/point_filter.hpp"
#include "recon/area_volume.hpp"
#include "viewer/picking.hpp"
#include "viewer/scene_snapshot.hpp"

namespace lidarscout::viewer {

// Throws lidarscout::Error (stage "measure") as measure_area_volume does.
recon::AreaVolume measure_area(const SceneSnapshot& snapshot, std::span<const PickedPoint> polygon,
                               const PointFilter& filter);

// The measurement's summary line, or the reason it could not be made ("area: ..." either way).
std::string area_line(const SceneSnapshot& snapshot, std::span<const PickedPoint> polygon, const PointFilter& filter);

}  // namespace lidarscout::viewer
