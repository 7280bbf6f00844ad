// Entwine Point Tile (EPT) datasets as tile lists: the metadata file (ept.json, or the older
// entwine.json) and its JSON hierarchy name the LAZ nodes, which become the tiles. Works for
// local paths and URLs alike (read through io::File). Nodes the hierarchy counts as empty are
// left out; sub-hierarchy files (a count of -1) are followed.
#pragma once

#include <string>
#include <vector>

namespace lidarscout::dataset {

// True when the file name is ept.json or entwine.json.
bool is_ept_metadata(const std::string& path);

struct EptNodes {
    std::vector<std::string> tiles;   // the LAZ nodes, paths or URLs, in key order
    std::vector<std::string> errors;  // one line per file that could not be read or understood
};

EptNodes ept_nodes(const std::string& metadata_path);

}  // namespace lidarscout::dataset
