// The CLI edge of levelled diagnostics: one stderr line each for people ("lidarscout: warning:
// MESSAGE", as before) and, for --json, `diagnostics`: [{"level", "file" (or null), "offset"
// (bytes, or null), "message"}] (next to `warnings`, Diagnostics::messages(), as before).
#pragma once

#include <nlohmann/json.hpp>

#include "core/diagnostic.hpp"

namespace lidarscout::cli {

void print_diagnostics(const Diagnostics& diagnostics);

nlohmann::json diagnostics_json(const Diagnostics& diagnostics);

}  // namespace lidarscout::cli
