// The CLI edge of levelled diagnostics: one stderr line each for people ("lidarscout: warning:
// MESSAGE", as before) and, for --json, `diagnostics`: [{"level", "file" (or null), "offset"
// (bytes, or null), "message"}] (next to `warnings`, Diagnostics::messages(), as before).
#pragma once

#include <nlohmann/json.hpp>

#include <vector>

#include "core/diagnostic.hpp"
#include "core/error.hpp"

namespace lidarscout::cli {

void print_diagnostics(const Diagnostics& diagnostics);

// The exit status of a command that wrote its product without some data (a corrupt LAZ chunk, an
// unreadable tile): 3; 0 when nothing was skipped.
inline constexpr int kExitWrittenWithSkips = 3;
int written_exit_status(bool anything_skipped);

// One stderr line per record left out: "lidarscout: skipped FILE: at byte N: CAUSE".
void print_skipped(const std::vector<ErrorRecord>& skipped);
// The records as JSON: [{"file", "offset" (bytes, or null), "cause"}].
nlohmann::json skipped_json(const std::vector<ErrorRecord>& skipped);

nlohmann::json diagnostics_json(const Diagnostics& diagnostics);

}  // namespace lidarscout::cli
