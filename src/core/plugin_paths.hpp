// Where lidarscout's optional plugins (the LibTorch runner, the CUDA rasterizer) are looked
// for: the path in an environment variable, next to the program, in ../lib/lidarscout from
// it, and in the build tree the program was built in.
#pragma once

#include <string>
#include <vector>

namespace lidarscout {

// The folder of the running executable (empty when it cannot be told).
std::string executable_dir();

// Candidate paths of plugin `file_name`, in the order above; `env_var` names the override,
// `build_dir` is the build tree ("" for none).
std::vector<std::string> plugin_candidates(const char* env_var, const std::string& file_name,
                                           const std::string& build_dir);

}  // namespace lidarscout
