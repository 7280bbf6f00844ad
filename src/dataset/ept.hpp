// Entwine Point Tile (EPT) datasets as tile lists: the metadata file (ept.json, or the older
// entwine.json) and its JSON hierarchy name the LAZ nodes, which become the tiles. Works for
// local paths and URLs alike (read through io::File). Nodes the hierarchy counts as empty are
// left out; sub-hierarchy files (a count of -1) are followed.
//
// A hierarchy is read as a set of visited nodes: each hierarchy file is read at most once
// (one that names files already read, a DAG or a cycle, costs nothing more), and the nodes
// and the hierarchy's bytes are bounded (EptLimits, named in the error when passed). Every
// key must be a node key "D-X-Y-Z" (four numbers), so node and hierarchy files always lie
// inside the dataset's folders: a key cannot name an absolute path, another host or scheme.
// Remote datasets' derived URLs are also checked against the origin policy
// (net/origin_policy.hpp).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

namespace lidarscout::dataset {

// True when the file name is ept.json or entwine.json.
bool is_ept_metadata(const std::string& path);

struct EptLimits {
    std::uint64_t max_nodes = 4'000'000;             // hierarchy entries (nodes and sub-hierarchies)
    std::uint64_t max_hierarchy_bytes = 1ull << 30;  // all hierarchy files together
};

struct EptNodes {
    std::vector<std::string> tiles;   // the LAZ nodes, paths or URLs, in key order
    std::vector<std::string> errors;  // one line per file that could not be read or understood
    std::uint64_t hierarchy_files = 0;  // hierarchy files read
};

EptNodes ept_nodes(const std::string& metadata_path, const EptLimits& limits = {});

}  // namespace lidarscout::dataset
