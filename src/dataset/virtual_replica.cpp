// Reading virtual replica manifests (through the bounded JSON reader, each field by its kind) and
// shifting a tile's header.
#include "dataset/virtual_replica.hpp"

#include <nlohmann/json.hpp>

#include <cmath>
#include <filesystem>
#include <fstream>

#include "core/error.hpp"
#include "core/json_reader.hpp"
#include "core/regular_file.hpp"
#include "dataset/json_file.hpp"
#include "io/file.hpp"

namespace lidarscout::dataset {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

constexpr std::size_t kSniffBytes = 4096;

// The manifest's JSON, read by the bounded reader; throws Error naming it.
json parse_manifest(const std::string& path) {
    JsonLimits limits;
    limits.max_bytes = 256ull << 20;
    limits.kept = {4'000'000, 64ull << 20};
    require_regular_file(path);  // refused as it is, not as a bad manifest
    try {
        return read_json_object(io::File::open(path), limits);
    } catch (const Error& e) {
        throw Error(path, e.offset(), "not a valid virtual replica manifest: " + e.cause());
    }
}

ShiftedSource tile_of(const json& t, const std::vector<std::string>& sources) {
    const auto index = json_optional_count(t, "source");
    const json& shift = json_array(t, "shift");
    if (!index || *index >= sources.size() || shift.size() != 2) throw Error("a tile's source or shift is invalid");
    return {sources[*index], {json_finite(shift[0], "a shift"), json_finite(shift[1], "a shift")},
            json_optional_string(t, "file").value_or("")};
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
    try {
        if (!json_optional_bool(m, "virtual").value_or(false)) {
            throw Error("not a virtual replica (no \"virtual\": true)");
        }
        std::vector<std::string> sources;
        for (const auto& s : json_array(m, "sources")) sources.push_back(json_string(s, "path"));
        std::vector<ShiftedSource> out;
        for (const auto& t : json_array(m, "tiles")) out.push_back(tile_of(t, sources));
        return out;
    } catch (const Error& e) {
        throw Error(path, std::nullopt, "virtual replica manifest: " + e.cause());
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
