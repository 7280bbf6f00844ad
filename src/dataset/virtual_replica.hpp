// Virtual replicas (`synth replicate --virtual`), a benchmark tool: a manifest (replicate.json
// with "virtual": true) lists tiles, each a source tile and an x/y shift in the source's units;
// the dataset opens them as tiles without copying anything. A virtual tile reads its source
// file; only its header's x/y offsets and bounds (and a COPC centre) are moved, which shifts
// every point, since LAS point records are integers relative to the header's scale and offset.
#pragma once

#include <array>
#include <string>
#include <vector>

#include "dataset/tile.hpp"

namespace lidarscout::dataset {

// The manifest's keys that mark it (written by synth/replicate.cpp).
inline constexpr const char* kReplicaTool = "lidarscout synth replicate";
// The manifest's name in the replica's folder; a folder holding a virtual one opens as the replica.
inline constexpr const char* kReplicaManifestName = "replicate.json";

struct ShiftedSource {
    std::string path;               // the source tile (absolute)
    std::array<double, 2> shift{};  // added to its x/y offsets and bounds, in its own units
    std::string name;               // the tile's name in the grid (e.g. STEM_x3_y4.laz), for display
};

// True when `path` is a virtual replica manifest: a .json file whose first 4 KiB name the tool and
// hold "virtual": true (an EPT ept.json or any other JSON is not one).
bool is_virtual_replica(const std::string& path);

// The tiles of a virtual replica manifest, in its order. Throws lidarscout::Error (naming the
// manifest) when it cannot be read or is malformed (a missing field, a source index out of
// range, a shift that is not finite).
std::vector<ShiftedSource> read_virtual_replica(const std::string& path);

// Moves `tile`'s x/y offsets, bounds and COPC centre by `shift` (its own units).
void shift_tile(Tile& tile, std::array<double, 2> shift);

}  // namespace lidarscout::dataset
