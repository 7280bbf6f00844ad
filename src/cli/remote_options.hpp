// Options every command that reads datasets has for remote (http/https) ones: the size of
// the on-disk cache of fetched ranges (net/range_cache.hpp), the CAs that TLS servers are
// verified with, the minimum rate of a request's deadline and the merge gap (net/http_client.hpp), and the
// other origins a dataset may lead to (net/origin_policy.hpp).
#pragma once

#include <CLI/CLI.hpp>

namespace lidarscout::cli {

// Adds --cache-size, --cacert, --allow-origins, --min-rate and --merge-gap to `cmd`; their values configure
// the process's range cache, HTTP client and origin policy when parsed.
void add_remote_options(CLI::App& cmd);

// A check for an input path: an existing file, or an http(s) URL (checked when it is read).
CLI::Validator existing_file_or_url();

}  // namespace lidarscout::cli
