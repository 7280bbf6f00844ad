// The viewer's area tool without window code: the polygon clicked on the ground measured on the points
// `lidarscout clip` and the tool's own clip-out write. The tiles it touches are read again through
// pipelines::read_region_points with the polygon in the dataset CRS's units (area_region, which the
// clip-out uses too): the same decoded coordinates, the same point test and filter, so its point count
// is the clip's. The points are then placed in world metres for its area, surface, and the volume
// above and below the plane through its vertices (recon/area_volume.hpp).
#pragma once

#include <cstdint>
#include <span>
#include <string>

#include "core/point_filter.hpp"
#include "dataset/dataset.hpp"
#include "pipelines/region_points.hpp"
#include "recon/area_volume.hpp"
#include "viewer/picking.hpp"

namespace lidarscout {
class ThreadPool;
}

namespace lidarscout::viewer {

// The most points a measurement holds (24 bytes each): a larger area is refused, naming the clip.
inline constexpr std::uint64_t kMaxAreaPoints = 20'000'000;

// The polygon (vertices in world metres) as a region in the dataset CRS's units; throws
// lidarscout::Error (stage "polygon") for fewer than 3 distinct vertices.
pipelines::Region area_region(const dataset::Dataset& ds, std::span<const PickedPoint> polygon);

// Throws lidarscout::Error (stage "measure") as measure_area_volume does, when the polygon holds more
// than kMaxAreaPoints points that `filter` keeps, and when `watch` cancels it ("measure: cancelled").
recon::AreaVolume measure_area(const dataset::Dataset& ds, std::span<const PickedPoint> polygon,
                               const PointFilter& filter, ThreadPool& pool, const pipelines::ReadWatch& watch = {});

// The measurement's summary line, or the reason it could not be made ("area: ..." either way).
std::string area_line(const dataset::Dataset& ds, std::span<const PickedPoint> polygon, const PointFilter& filter,
                      ThreadPool& pool, const pipelines::ReadWatch& watch = {});

}  // namespace lidarscout::viewer
