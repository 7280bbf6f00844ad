// Reading `.lidarscout.json` sessions through the bounded JSON reader, each field by its kind, and
// writing them (fields this version does not know written back compact).
#include "viewer/session_file.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <fstream>
#include <set>

#include "core/error.hpp"
#include "core/json_reader.hpp"
#include "core/regular_file.hpp"
#include "io/output_file.hpp"
#include "render/colour_modes.hpp"

namespace lidarscout::viewer {
namespace {

using nlohmann::json;

const std::set<std::string> kKnown = {"version", "paths", "crs", "camera", "filter", "colour", "measurements",
                                      "annotations", "profiles", "kind"};
constexpr const char* kKind = "lidarscout session";
constexpr std::uint64_t kMaxSessionBytes = 64ull << 20;

json filter_json(const PointFilter& f) {
    return {{"classes", f.class_list()},
            {"returns", f.return_list()},
            {"intensity", f.intensity_min == 0 && f.intensity_max == 65535
                              ? std::string()
                              : std::to_string(f.intensity_min) + "-" + std::to_string(f.intensity_max)}};
}

// "1e+08": a number in a line.
std::string number_text(double v) {
    char text[32];
    std::snprintf(text, sizeof text, "%g", v);
    return text;
}

// `value` (of `what`), refused outside [low, high] naming the range and its `unit`.
double within(double value, const std::string& what, double low, double high, const char* unit) {
    if (value >= low && value <= high) return value;
    throw Error(what + " is " + number_text(value) + ", outside the range " + number_text(low) + " to " +
                number_text(high) + " " + unit);
}

// `n` finite numbers of the array `key` of `object` (`shape` names it in the error, "[x, y, z]"), each
// within +-session_range::kCoordinate (`unit` names them).
template <std::size_t n>
std::array<double, n> numbers(const json& object, const char* key, const char* shape, const char* unit) {
    const json& a = json_array(object, key);
    if (a.size() != n) throw Error("\"" + std::string(key) + "\" is not " + shape);
    std::array<double, n> out{};
    for (std::size_t k = 0; k < n; ++k) {
        const std::string what = "a number of \"" + std::string(key) + "\"";
        out[k] = within(json_finite(a[k], what), what, -session_range::kCoordinate, session_range::kCoordinate, unit);
    }
    return out;
}

std::array<double, 3> xyz(const json& object, const char* key) {
    return numbers<3>(object, key, "[x, y, z]", "(world metres)");
}

// The camera's pose: a number out of range refused, but a yaw wrapped and a pitch from -90 to 90
// clamped to the camera's range, each with a note in `notes` naming `path`.
CameraPose camera_from(const json& j, const std::string& path, Diagnostics& notes) {
    const auto note = [&](const std::string& what) {
        notes.add({DiagnosticLevel::note, path, std::nullopt, path + ": camera: " + what});
    };
    namespace r = session_range;
    CameraPose c;
    c.target = xyz(j, "target");
    c.distance = within(json_number(j, "distance"), "\"distance\"", r::kMinDistance, r::kMaxDistance, "(metres)");
    const double yaw = json_number(j, "yaw_deg");
    c.yaw_deg = wrapped_degrees(yaw);
    if (c.yaw_deg != yaw) {
        note("\"yaw_deg\" " + number_text(yaw) + " is read as " + number_text(c.yaw_deg) +
             " (the same heading, from -180 to 180)");
    }
    const double pitch = within(json_number(j, "pitch_deg"), "\"pitch_deg\"", -90, 90, "(degrees)");
    c.pitch_deg = std::clamp(pitch, r::kMinPitch, r::kMaxPitch);
    if (c.pitch_deg != pitch) {
        note("\"pitch_deg\" " + number_text(pitch) + " is read as " + number_text(c.pitch_deg) +
             " (the camera's range is " + number_text(r::kMinPitch) + " to " + number_text(r::kMaxPitch) + " degrees)");
    }
    c.fov_deg = within(json_optional_number(j, "fov_deg").value_or(60.0), "\"fov_deg\"", r::kMinFov, r::kMaxFov,
                       "(degrees)");
    return c;
}

// A profile's corridor: its ends within range and apart, its width within range.
SavedProfile profile_from(const json& p) {
    const SavedProfile out{numbers<4>(p, "line", "[x0, y0, x1, y1]", "(CRS units)"),
                           json_optional_number(p, "width").value_or(2.0)};
    if (!(out.width > 0)) throw Error("a profile's width is not positive");
    within(out.width, "\"width\"", 0, session_range::kMaxProfileWidth, "(CRS units, more than 0)");
    if (out.line[0] == out.line[2] && out.line[1] == out.line[3]) {
        throw Error("the two ends of \"line\" are the same point");
    }
    return out;
}

// Reads each element of the array `key` (when there is one) with `read`; an error names the array.
template <typename Read>
void each(const json& j, const char* key, Read&& read) {
    const json* array = json_optional_array(j, key);
    if (!array) return;
    for (std::size_t i = 0; i < array->size(); ++i) {
        try {
            read((*array)[i]);
        } catch (const Error& e) {
            throw Error(std::string(key) + " #" + std::to_string(i + 1) + ": " + e.cause());
        }
    }
}

// The version, which this program must know: a whole number from 1 to kSessionVersion.
int session_version(const json& j) {
    const json* v = json_field(j, "version");
    if (!v) throw Error("a session without a \"version\"");
    if (v->is_number_integer()) {  // (signed or unsigned)
        const bool newer = v->is_number_unsigned() ? v->get<std::uint64_t>() > kSessionVersion
                                                   : v->get<std::int64_t>() > kSessionVersion;
        if (newer) {
            throw Error("a session of version " + json_excerpt(*v) + ", newer than this program's (" +
                        std::to_string(kSessionVersion) + "): update lidarscout");
        }
        if (v->get<std::int64_t>() >= 1) return static_cast<int>(v->get<std::int64_t>());
    }
    throw Error("\"version\": " + json_excerpt(*v) + " is not a supported session version (this program reads 1 to " +
                std::to_string(kSessionVersion) + ")");
}

void read_fields(const json& j, SessionFile& s, const std::string& path) {
    s.version = session_version(j);
    each(j, "paths", [&](const json& p) {
        if (!p.is_string()) throw Error("is " + json_kind(p) + ", not a string");
        s.paths.push_back(p.get<std::string>());
    });
    s.crs = json_optional_string(j, "crs").value_or("");
    if (const json* camera = json_optional_object(j, "camera")) {
        try {
            s.camera = camera_from(*camera, path, s.notes);
        } catch (const Error& e) {
            throw Error("camera: " + e.cause());
        }
    }
    if (const json* f = json_optional_object(j, "filter")) {
        s.filter = PointFilter::parse(json_optional_string(*f, "classes").value_or(""),
                                      json_optional_string(*f, "returns").value_or(""),
                                      json_optional_string(*f, "intensity").value_or(""));
    }
    s.colour = json_optional_string(j, "colour").value_or("");
    if (!s.colour.empty()) render::parse_colour_mode(s.colour);  // refused here, not when applied
    each(j, "measurements", [&](const json& m) { s.measurements.push_back({xyz(m, "from"), xyz(m, "to")}); });
    each(j, "annotations", [&](const json& a) { s.annotations.push_back({xyz(a, "at"), json_string(a, "text")}); });
    each(j, "profiles", [&](const json& p) { s.profiles.push_back(profile_from(p)); });
}

// A known field's value as written: indented for a person, under its key's indentation.
std::string indented(const json& value) {
    std::string text = value.dump(2, ' ', false, json::error_handler_t::replace), out;
    out.reserve(text.size());
    for (const char c : text) out += c == '\n' ? std::string("\n  ") : std::string(1, c);
    return out;
}

}  // namespace

double wrapped_degrees(double degrees) {
    const double d = std::fmod(degrees + 180.0, 360.0);  // (exact)
    return (d < 0 ? d + 360.0 : d) - 180.0;
}

json session_json(const SessionFile& s) {
    json j = s.unknown;
    j["kind"] = kKind;
    j["version"] = s.version;
    j["paths"] = s.paths;
    j["crs"] = s.crs;
    if (s.camera) {
        j["camera"] = {{"target", s.camera->target}, {"distance", s.camera->distance},
                       {"yaw_deg", wrapped_degrees(s.camera->yaw_deg)},
                       {"pitch_deg", s.camera->pitch_deg}, {"fov_deg", s.camera->fov_deg}};
    }
    j["filter"] = filter_json(s.filter);
    j["colour"] = s.colour;
    j["measurements"] = json::array();
    for (const auto& m : s.measurements) j["measurements"].push_back({{"from", m.from}, {"to", m.to}});
    j["annotations"] = json::array();
    for (const auto& a : s.annotations) j["annotations"].push_back({{"at", a.at}, {"text", a.text}});
    j["profiles"] = json::array();
    for (const auto& p : s.profiles) j["profiles"].push_back({{"line", p.line}, {"width", p.width}});
    return j;
}

std::string session_text(const SessionFile& session) {
    const json j = session_json(session);
    std::string out = "{";
    const char* separator = "\n  ";
    for (const auto& [key, value] : j.items()) {
        out += separator + json(key).dump(-1, ' ', false, json::error_handler_t::replace) + ": ";
        // fields this version does not know are kept compact: indenting them costs their depth per line
        out += kKnown.contains(key) ? indented(value) : value.dump(-1, ' ', false, json::error_handler_t::replace);
        separator = ",\n  ";
    }
    return out + "\n}\n";
}

SessionFile session_from_json(const json& j, const std::string& path) {
    const json* kind = json_field(j, "kind");
    if (!kind || !kind->is_string() || kind->get_ref<const std::string&>() != kKind) {
        throw Error(path, std::nullopt, "not a lidarscout session (no \"kind\": \"" + std::string(kKind) + "\")");
    }
    SessionFile s;
    try {
        read_fields(j, s, path);
    } catch (const Error& e) {
        if (!e.file().empty()) throw;
        throw e.with_file(path);  // the field's or the filter's message, with the file
    }
    for (const auto& [key, value] : j.items()) {
        if (!kKnown.contains(key)) s.unknown[key] = value;
    }
    return s;
}

SessionFile read_session(const std::string& path) {
    require_regular_file(path);  // a FIFO would hang the read
    std::ifstream in(path, std::ios::binary);
    if (!in) throw Error(path, std::nullopt, "cannot open the session file");
    JsonLimits limits;
    limits.max_bytes = kMaxSessionBytes;
    return session_from_json(read_json(istream_json_source(in), path, limits), path);
}

void write_session(const std::string& path, const SessionFile& session) {
    const std::string text = session_text(session);
    io::AtomicOutputFile out(path);
    out.write({reinterpret_cast<const std::uint8_t*>(text.data()), text.size()});
    out.commit();
}

}  // namespace lidarscout::viewer
