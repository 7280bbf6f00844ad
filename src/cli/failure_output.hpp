// How a failed command ends at the CLI edge: one line on stderr ("lidarscout: FILE: CAUSE") and,
// when --json was asked for, one valid JSON object on stdout, so that scripts never parse an
// empty or partial answer:
//   {"error": {"kind": "input" | "usage" | "memory" | "internal", "message": the line's text,
//              "file": FILE or null, "offset": bytes or null, "cause": CAUSE}}
#pragma once

#include <optional>
#include <string>

#include "core/error.hpp"

namespace lidarscout::cli {

struct Failure {
    std::string kind;     // "input" (a lidarscout::Error), "usage", "memory", "internal"
    std::string message;  // the whole line, without the "lidarscout: " prefix
    std::string file;
    std::optional<std::uint64_t> offset;
    std::string cause;

    static Failure of(const Error& error);
};

// Prints the line on stderr and, with `json`, the object on stdout.
void report_failure(const Failure& failure, bool json);

}  // namespace lidarscout::cli
