// Options every command that reads datasets has for remote (http/https) ones: the size of
// the on-disk cache of fetched ranges (net/range_cache.hpp).
#pragma once

#include <CLI/CLI.hpp>

namespace lidarscout::cli {

// Adds --cache-size to `cmd`; its value configures the process's range cache when parsed.
void add_remote_options(CLI::App& cmd);

// A check for an input path: an existing file, or an http(s) URL (checked when it is read).
CLI::Validator existing_file_or_url();

}  // namespace lidarscout::cli
