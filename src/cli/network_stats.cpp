// Requests and bytes of remote reads, for the commands' JSON.
#include "cli/network_stats.hpp"

namespace lidarscout::cli {

net::HttpStats network_since(const net::HttpStats& before) {
    const net::HttpStats now = net::HttpClient::shared().stats();
    net::HttpStats d;
    d.requests = now.requests - before.requests;
    d.body_bytes = now.body_bytes - before.body_bytes;
    d.header_bytes = now.header_bytes - before.header_bytes;
    d.retries = now.retries - before.retries;
    d.opens_in_one = now.opens_in_one - before.opens_in_one;
    d.open_fallbacks = now.open_fallbacks - before.open_fallbacks;
    return d;
}

nlohmann::json network_json(const net::HttpStats& stats, std::size_t tiles) {
    const std::uint64_t bytes = stats.body_bytes + stats.header_bytes;
    const double per = tiles ? 1.0 / static_cast<double>(tiles) : 0.0;
    return {{"requests", stats.requests},
            {"bytes", bytes},
            {"retries", stats.retries},
            {"opens_in_one_request", stats.opens_in_one},
            {"open_fallbacks", stats.open_fallbacks},
            {"requests_per_tile", static_cast<double>(stats.requests) * per},
            {"bytes_per_tile", static_cast<double>(bytes) * per}};
}

}  // namespace lidarscout::cli
