// A saved viewer session (`.lidarscout.json`), without window code: what was open (paths or URLs,
// the CRS asked for), the camera, the filter and colour mode, the measurements, the
// annotations (text labels at picked points) and the profiles' corridors. Positions are world
// metres of the dataset's frame (the CRS named in the file), but a profile's line and width are in
// that CRS's units, as `view --profile` and `lidarscout profile --line` take them. The file has a
// `version`; a field this version does not know is kept and written back as it was (compact), so
// that a newer program's sessions survive an older one. Files are read by the bounded JSON reader
// (core/json_reader.hpp: depth, string and size limits), each field by its kind.
#pragma once

#include <array>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "core/point_filter.hpp"

namespace lidarscout::viewer {

inline constexpr int kSessionVersion = 1;

// The orbit camera (viewer::app::CameraController's state).
struct CameraPose {
    std::array<double, 3> target{};  // the point orbited, world metres
    double distance = 1000, yaw_deg = 0, pitch_deg = -60, fov_deg = 60;
    bool operator==(const CameraPose&) const = default;
};

struct Annotation {
    std::array<double, 3> at{};  // world metres
    std::string text;
    bool operator==(const Annotation&) const = default;
};

struct SavedMeasurement {
    std::array<double, 3> from{}, to{};  // world metres
    bool operator==(const SavedMeasurement&) const = default;
};

// A profile's corridor: the line x0, y0, x1, y1 and its full width (the dataset CRS's units).
struct SavedProfile {
    std::array<double, 4> line{};
    double width = 2;
    bool operator==(const SavedProfile&) const = default;
};

struct SessionFile {
    int version = kSessionVersion;
    std::vector<std::string> paths;  // as given to `view` (files, folders, lists, URLs)
    std::string crs;                 // the CRS tiles were reprojected to ("" = the majority's)
    std::optional<CameraPose> camera;
    PointFilter filter;
    std::string colour;  // render::colour_mode_name ("" = the viewer's default)
    std::vector<SavedMeasurement> measurements;
    std::vector<Annotation> annotations;
    std::vector<SavedProfile> profiles;
    nlohmann::json unknown = nlohmann::json::object();  // fields this version does not read, kept
};

// Reads `path`; throws lidarscout::Error (the file, the cause) when it cannot be read, is not
// JSON or passes the reader's limits, is not a session (no "kind" naming one), has a field of the
// wrong kind, or has a version this program does not read (not a whole number from 1 to
// kSessionVersion: a newer one is told to update).
SessionFile read_session(const std::string& path);
// Writes `session` to `path` through a temporary name (refused when it names an input).
void write_session(const std::string& path, const SessionFile& session);

nlohmann::json session_json(const SessionFile& session);
// The file's text: known fields indented, unknown ones compact (so its size follows what they hold).
std::string session_text(const SessionFile& session);
// Throws lidarscout::Error naming `path` (used in the message only).
SessionFile session_from_json(const nlohmann::json& j, const std::string& path);

}  // namespace lidarscout::viewer
