// A command's JSON answer on stdout (--json): one object, indented, flushed. Text taken from files (paths, ids,
// messages that quote them) need not be UTF-8; such bytes come out as U+FFFD instead of ending the command
// (nlohmann's dump throws on them: a damaged sidecar's table made `scan --json` an internal error).
#pragma once

#include <nlohmann/json.hpp>

#include <string>

namespace lidarscout::cli {

// The object's text, indented by two, invalid UTF-8 replaced.
std::string json_text(const nlohmann::json& j);
// json_text and a newline on stdout, flushed.
void print_json_answer(const nlohmann::json& j);

}  // namespace lidarscout::cli
