// Finding the tiles of a dataset: paths given by the user, folders searched recursively for
// .las/.laz files (case-insensitive), in a stable sorted order.
#pragma once

#include <string>
#include <vector>

namespace lidarscout::dataset {

struct FoundFiles {
    std::vector<std::string> files;   // LAS/LAZ files, folders expanded, sorted per argument
    std::vector<std::string> errors;  // one message per path that does not exist / cannot be listed
};

bool has_point_cloud_extension(const std::string& path);

// Expands every path: a file is kept as given (whatever its extension), a folder is searched
// recursively for .las/.laz files.
FoundFiles find_point_cloud_files(const std::vector<std::string>& paths);

}  // namespace lidarscout::dataset
