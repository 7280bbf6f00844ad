// Options every command that reads datasets has for remote (http/https) ones: the size of
// the on-disk cache of fetched ranges (net/range_cache.hpp) and the CAs that TLS servers are
// verified with (net/http_client.hpp).
#pragma once

#include <CLI/CLI.hpp>

namespace lidarscout::cli {

// Adds --cache-size and --cacert to `cmd`; their values configure the process's range cache
// and HTTP client when parsed.
void add_remote_options(CLI::App& cmd);

// A check for an input path: an existing file, or an http(s) URL (checked when it is read).
CLI::Validator existing_file_or_url();

}  // namespace lidarscout::cli
