// What a command's remote reads cost, for its JSON: requests and bytes of the process's HTTP
// client (net/http_client.hpp) since a point, and per tile read (`scan --json`, `view --stats-json`).
#pragma once

#include <cstddef>

#include <nlohmann/json.hpp>

#include "net/http_client.hpp"

namespace lidarscout::cli {

// What the process's HTTP client did between `before` (its stats() then) and now.
net::HttpStats network_since(const net::HttpStats& before);

// {"requests", "bytes" (response bodies and headers), "retries", "opens_in_one_request", "open_fallbacks"
// (net/remote_file.hpp), "requests_per_tile", "bytes_per_tile"}: all 0 for local tiles.
nlohmann::json network_json(const net::HttpStats& stats, std::size_t tiles);

}  // namespace lidarscout::cli
