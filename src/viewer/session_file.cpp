// Reading and writing `.lidarscout.json` sessions.
#include "viewer/session_file.hpp"

#include <fstream>
#include <iterator>
#include <set>

#include "core/error.hpp"
#include "core/regular_file.hpp"
#include "io/output_file.hpp"
#include "render/colour_modes.hpp"

namespace lidarscout::viewer {
namespace {

const std::set<std::string> kKnown = {"version", "paths", "crs", "camera", "filter", "colour", "measurements",
                                      "annotations", "profiles", "kind"};
constexpr const char* kKind = "lidarscout session";

nlohmann::json filter_json(const PointFilter& f) {
    return {{"classes", f.class_list()},
            {"returns", f.return_list()},
            {"intensity", f.intensity_min == 0 && f.intensity_max == 65535
                              ? std::string()
                              : std::to_string(f.intensity_min) + "-" + std::to_string(f.intensity_max)}};
}

std::array<double, 3> xyz(const nlohmann::json& j) { return {j.at(0).get<double>(), j.at(1).get<double>(),
                                                             j.at(2).get<double>()}; }

CameraPose camera_from(const nlohmann::json& j) {
    CameraPose c;
    c.target = xyz(j.at("target"));
    c.distance = j.at("distance").get<double>();
    c.yaw_deg = j.at("yaw_deg").get<double>();
    c.pitch_deg = j.at("pitch_deg").get<double>();
    c.fov_deg = j.value("fov_deg", 60.0);
    return c;
}

}  // namespace

nlohmann::json session_json(const SessionFile& s) {
    nlohmann::json j = s.unknown;
    j["kind"] = kKind;
    j["version"] = s.version;
    j["paths"] = s.paths;
    j["crs"] = s.crs;
    if (s.camera) {
        j["camera"] = {{"target", s.camera->target}, {"distance", s.camera->distance}, {"yaw_deg", s.camera->yaw_deg},
                       {"pitch_deg", s.camera->pitch_deg}, {"fov_deg", s.camera->fov_deg}};
    }
    j["filter"] = filter_json(s.filter);
    j["colour"] = s.colour;
    j["measurements"] = nlohmann::json::array();
    for (const auto& m : s.measurements) j["measurements"].push_back({{"from", m.from}, {"to", m.to}});
    j["annotations"] = nlohmann::json::array();
    for (const auto& a : s.annotations) j["annotations"].push_back({{"at", a.at}, {"text", a.text}});
    j["profiles"] = nlohmann::json::array();
    for (const auto& p : s.profiles) j["profiles"].push_back({{"line", p.line}, {"width", p.width}});
    return j;
}

SessionFile session_from_json(const nlohmann::json& j, const std::string& path) {
    if (!j.is_object() || j.value("kind", std::string()) != kKind) {
        throw Error(path, std::nullopt, "not a lidarscout session (no \"kind\": \"" + std::string(kKind) + "\")");
    }
    SessionFile s;
    try {
        s.version = j.at("version").get<int>();
        if (s.version > kSessionVersion) {
            throw Error(path, std::nullopt, "a session of version " + std::to_string(s.version) +
                                                ", newer than this program's (" + std::to_string(kSessionVersion) +
                                                "): update lidarscout");
        }
        s.paths = j.value("paths", std::vector<std::string>{});
        s.crs = j.value("crs", std::string());
        if (j.contains("camera")) s.camera = camera_from(j.at("camera"));
        if (j.contains("filter")) {
            const auto& f = j.at("filter");
            s.filter = PointFilter::parse(f.value("classes", ""), f.value("returns", ""), f.value("intensity", ""));
        }
        s.colour = j.value("colour", std::string());
        if (!s.colour.empty()) render::parse_colour_mode(s.colour);  // refused here, not when applied
        for (const auto& m : j.value("measurements", nlohmann::json::array())) {
            s.measurements.push_back({xyz(m.at("from")), xyz(m.at("to"))});
        }
        for (const auto& a : j.value("annotations", nlohmann::json::array())) {
            s.annotations.push_back({xyz(a.at("at")), a.at("text").get<std::string>()});
        }
        for (const auto& p : j.value("profiles", nlohmann::json::array())) {
            const auto& l = p.at("line");
            if (l.size() != 4) throw Error(path, std::nullopt, "a profile's \"line\" is not [x0, y0, x1, y1]");
            s.profiles.push_back({{l.at(0).get<double>(), l.at(1).get<double>(), l.at(2).get<double>(),
                                   l.at(3).get<double>()},
                                  p.value("width", 2.0)});
            if (!(s.profiles.back().width > 0)) throw Error(path, std::nullopt, "a profile's width is not positive");
        }
    } catch (const nlohmann::json::exception& e) {
        throw Error(path, std::nullopt, std::string("a session field is missing or of the wrong kind: ") + e.what());
    } catch (const Error& e) {
        if (!e.file().empty()) throw;
        throw e.with_file(path);  // the filter's own message, with the file
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
    const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    const auto j = nlohmann::json::parse(text, nullptr, false);
    if (j.is_discarded()) throw Error(path, std::nullopt, "not JSON");
    return session_from_json(j, path);
}

void write_session(const std::string& path, const SessionFile& session) {
    const std::string text = session_json(session).dump(2) + "\n";
    io::AtomicOutputFile out(path);
    out.write({reinterpret_cast<const std::uint8_t*>(text.data()), text.size()});
    out.commit();
}

}  // namespace lidarscout::viewer
