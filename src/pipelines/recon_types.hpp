// The pipelines run recon's per-patch algorithms over whole datasets: recon's types (PatchSpec,
// Method, Reconstruction, ...) are used in this stage as its own, declared here once.
#pragma once

#include "recon/patch_space.hpp"

namespace lidarscout::pipelines {
using namespace lidarscout::recon;  // NOLINT(google-build-using-namespace)
}  // namespace lidarscout::pipelines
