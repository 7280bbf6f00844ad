// Usage errors through the program's own error path: a command line CLI11 refused becomes one
// Failure of kind "usage" (one line "lidarscout: COMMAND: ...", exit status 1, the JSON error with
// --json), never CLI11's own text and exit codes (105-114). The unknown command or option is named
// with the closest valid one ("unknown command 'clpi' (did you mean 'clip'?)", "profile: unknown
// option '--lines' (did you mean '--line'?)"), found by walking the command line over the CLI11
// app: a misspelt option is reported as such even when CLI11 first noticed the required option it
// left missing.
#pragma once

#include <string>
#include <string_view>
#include <vector>

#include "cli/failure_output.hpp"

namespace CLI {
class App;
class ParseError;
}  // namespace CLI

namespace lidarscout::cli {

// The failure to report for `error`, thrown by app.parse(argc, argv).
Failure usage_failure(const CLI::App& app, int argc, const char* const* argv, const CLI::ParseError& error);

// The candidate closest to `word` by edit distance (insertions, deletions, substitutions and
// swaps of two neighbours: "clpi" is one from "clip"), or the one it is the start of; "" when
// none is close (more than a third of the word, and more than one edit for short words).
std::string closest_name(std::string_view word, const std::vector<std::string>& candidates);

}  // namespace lidarscout::cli
