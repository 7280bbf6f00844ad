// Profiles (cross-sections): every full-resolution point in a corridor along a line segment, with
// its distance along the line, read with read_region_points (only the tiles touching the
// corridor), written as CSV or drawn as an image (distance against height, coloured by class).
// Coordinates, widths and distances are in the dataset CRS's units, as the command line gives them.
#pragma once

#include <cstdint>
#include <functional>
#include <span>
#include <string>
#include <vector>

#include "pipelines/region_points.hpp"

namespace lidarscout::pipelines {

// The segment (x0, y0) - (x1, y1) and the corridor's full width, in the frame CRS's units.
struct Corridor {
    double x0 = 0, y0 = 0, x1 = 0, y1 = 0, width = 2;
    double length() const;
    // Distance along the line from (x0, y0) and across it (signed), of (x, y).
    double along(double x, double y) const;
    double across(double x, double y) const;
    // |across| <= width / 2 and along in [0, length].
    bool contains(double x, double y) const;
    // Whether the corridor's rectangle and the box share a point (separating axes).
    bool touches_box(double min_x, double min_y, double max_x, double max_y) const;
};

// How the profile's messages name its region.
inline constexpr const char* kCorridor = "the line's corridor";

// The corridor as a region. Throws lidarscout::Error for a segment of length 0
// or a width that is not positive.
Region corridor_region(const Corridor& corridor);

struct ProfilePoint {
    double distance = 0, x = 0, y = 0, z = 0;  // the frame CRS's units
    std::uint16_t intensity = 0;
    std::uint8_t classification = 0, return_number = 0, number_of_returns = 0;
    std::uint32_t tile = 0;  // index in the dataset
};

struct Profile {
    std::vector<ProfilePoint> points;  // tile after tile, in file order
    RegionReadStats read;
    double seconds_to_first_points = -1, seconds = 0;  // -1: none found
};

// The points of each batch as they are read (who shows a profile while it is read).
using ProfilePointsFn = std::function<void(std::span<const ProfilePoint> points)>;

// Every point of the corridor passing `filter`; `watch` follows and may stop the read (the points
// read until then are returned, profile.read.cancelled set); `points` sees them batch by batch.
Profile read_profile(const dataset::Dataset& ds, const Corridor& corridor, const PointFilter& filter,
                     ThreadPool& pool, const ReadWatch& watch = {}, const ProfilePointsFn& points = nullptr);

// Throws lidarscout::Error (stage "profile") when `profile` (read_profile of `corridor` and `filter`)
// holds no point, saying why (require_touched_tiles, require_kept_points of the corridor).
void require_profile_points(const dataset::Dataset& ds, const Corridor& corridor, const PointFilter& filter,
                            const Profile& profile, ThreadPool& pool);

// CSV: distance,x,y,z,class,intensity,return,returns,source_file (a header line), through a
// temporary name. Throws lidarscout::Error.
void write_profile_csv(const std::string& path, const dataset::Dataset& ds, const Profile& profile);

}  // namespace lidarscout::pipelines
