// A saved viewer session (`.lidarscout.json`), without window code: what was open (paths or URLs,
// the CRS asked for), the camera, the filter and colour mode, the measurements, the
// annotations (text labels at picked points) and the profiles' corridors. Positions are world
// metres of the dataset's frame (the CRS named in the file), but a profile's line and width are in
// that CRS's units, as `view --profile` and `lidarscout profile --line` take them. The file has a
// `version`; a field this version does not know is kept and written back as it was (compact), so
// that a newer program's sessions survive an older one. Files are read by the bounded JSON reader
// (core/json_reader.hpp: depth, string and size limits), each field by its kind, and each number
// within its range (SessionRanges): outside it, refused in one line naming the file, the field and
// the range -- but a yaw, which wraps into -180 to 180, and a pitch from -90 to 90, which is clamped
// to the camera's range, each with a note.
#pragma once

#include <array>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "core/diagnostic.hpp"
#include "core/point_filter.hpp"

namespace lidarscout::viewer {

inline constexpr int kSessionVersion = 1;

// The ranges of a session's numbers: those of the camera as its controls keep it
// (viewer::app::CameraController), positions anywhere on (or far off) the Earth.
namespace session_range {
inline constexpr double kCoordinate = 1e8;  // |x|, |y|, |z| of a position (world metres) or a line's end (CRS units)
inline constexpr double kMinDistance = 1.0, kMaxDistance = 5e6;  // camera to target, metres
inline constexpr double kMinPitch = -89.5, kMaxPitch = 10.0;     // degrees (0 level, -90 straight down)
inline constexpr double kMinFov = 1.0, kMaxFov = 170.0;          // degrees, vertical
inline constexpr double kMaxProfileWidth = 1e6;                  // a corridor's full width, CRS units (> 0)
}  // namespace session_range

// `degrees` wrapped into [-180, 180).
double wrapped_degrees(double degrees);

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
    Diagnostics notes;  // what reading changed (a yaw wrapped, a pitch clamped), naming the file; not saved
};

// Reads `path`; throws lidarscout::Error (the file, the cause) when it cannot be read, is not
// JSON or passes the reader's limits, is not a session (no "kind" naming one), has a field of the
// wrong kind or a number outside its range (session_range: the field and range named), or has a
// version this program does not read (not a whole number from 1 to kSessionVersion: a newer one is
// told to update).
SessionFile read_session(const std::string& path);
// Writes `session` to `path` through a temporary name (refused when it names an input).
void write_session(const std::string& path, const SessionFile& session);

// The session as JSON (a yaw written wrapped into -180 to 180).
nlohmann::json session_json(const SessionFile& session);
// The file's text: known fields indented, unknown ones compact (so its size follows what they hold).
std::string session_text(const SessionFile& session);
// Throws lidarscout::Error naming `path` (used in the message only).
SessionFile session_from_json(const nlohmann::json& j, const std::string& path);

}  // namespace lidarscout::viewer
