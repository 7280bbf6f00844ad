// Finding and opening liblidarscout_torch.so, the LibTorch runner plugin (nn/runner_abi.h).
// Looked for, in order: $LIDARSCOUT_TORCH_RUNNER (a file), next to the running program, in
// ../lib/lidarscout/ beside it, and in the build folder this program was built in.
#pragma once

#include <string>
#include <vector>

#include "nn/runner_abi.h"

namespace lidarscout::nn {

inline constexpr char kRunnerFileName[] = "liblidarscout_torch.so";

// Candidate paths of the plugin, in the order above.
std::vector<std::string> runner_candidates();

// Opens the plugin once per process (later calls return the same table). Throws
// lidarscout::Error naming the places looked in, or the loader's message.
const LidarscoutRunnerApi& runner_api();

}  // namespace lidarscout::nn
