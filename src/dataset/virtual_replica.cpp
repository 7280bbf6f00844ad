// Reading virtual replica manifests and shifting a tile's header.
#include "dataset/virtual_replica.hpp"

#include <nlohmann/json.hpp>

#include <cmath>
#include <filesystem>
#include <fstream>

#include "core/error.hpp"
#include "core/regular_file.hpp"

namespace lidarscout::dataset {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

constexpr std::size_t kSniffBytes = 4096;

// The manifest's JSON; throws Error naming it.
json parse_manifest(const std::string& path) {
    require_regular_file(path);  // a FIFO would hang the read
    std::ifstream in(path);
    if (!in) throw Error(path, std::nullopt, "cannot read the virtual replica manifest");
    try {
        return json::parse(in);
    } catch (const json::exception& e) {
        throw Error(path, std::nullopt, std::string("not a valid virtual replica manifest: ") + e.what());
    }
}

const json& field(const json& object, const char* name, const std::string& path) {
    if (!object.is_object() || !object.contains(name)) {
        throw Error(path, std::nullopt, std::string("virtual replica manifest: missing \"") + name + "\"");
    }
    return object.at(name);
}

}  // namespace

bool is_virtual_replica(const std::string& path) {
    std::error_code ec;
    if (fs::path(path).extension() != ".json" || !fs::is_regular_file(path, ec)) return false;  // (a FIFO hangs)
    std::ifstream in(path);
    std::string head(kSniffBytes, '\0');
    in.read(head.data(), static_cast<std::streamsize>(head.size()));
    head.resize(static_cast<std::size_t>(in.gcount()));
    // The writer puts "tool" and "virtual" first (synth/replicate.cpp), so the head tells.
    return head.find(kReplicaTool) != std::string::npos && head.find("\"virtual\": true") != std::string::npos;
}

std::vector<ShiftedSource> read_virtual_replica(const std::string& path) {
    const json m = parse_manifest(path);
    if (!m.value("virtual", false)) throw Error(path, std::nullopt, "not a virtual replica (no \"virtual\": true)");
    std::vector<std::string> sources;
    try {
        for (const auto& s : field(m, "sources", path)) sources.push_back(field(s, "path", path).get<std::string>());
        std::vector<ShiftedSource> out;
        for (const auto& t : field(m, "tiles", path)) {
            const auto index = field(t, "source", path).get<std::size_t>();
            const auto& shift = field(t, "shift", path);
            if (index >= sources.size() || !shift.is_array() || shift.size() != 2) {
                throw Error(path, std::nullopt, "virtual replica manifest: a tile's source or shift is invalid");
            }
            ShiftedSource s{sources[index], {shift[0].get<double>(), shift[1].get<double>()}, t.value("file", "")};
            if (!std::isfinite(s.shift[0]) || !std::isfinite(s.shift[1])) {
                throw Error(path, std::nullopt, "virtual replica manifest: a shift is not finite");
            }
            out.push_back(std::move(s));
        }
        return out;
    } catch (const json::exception& e) {
        throw Error(path, std::nullopt, std::string("virtual replica manifest: ") + e.what());
    }
}

void shift_tile(Tile& tile, std::array<double, 2> shift) {
    for (int axis = 0; axis < 2; ++axis) {
        tile.header.offset[axis] += shift[axis];
        tile.header.min[axis] += shift[axis];
        tile.header.max[axis] += shift[axis];
        if (tile.copc) tile.copc->center[axis] += shift[axis];
    }
}

}  // namespace lidarscout::dataset
