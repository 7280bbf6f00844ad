// --cache-size: the bound of the on-disk cache of remote byte ranges; --cacert: the CAs to trust;
// --allow-origins: other origins a dataset's URLs may lead to; --min-rate: the request deadline;
// --requester-pays: s3 requests that the requester pays for.
#include "cli/remote_options.hpp"

#include <functional>

#include "cli/size_options.hpp"
#include "core/error.hpp"
#include "net/http_client.hpp"
#include "net/origin_policy.hpp"
#include "net/range_cache.hpp"
#include "net/s3_config.hpp"
#include "net/url.hpp"

namespace lidarscout::cli {

namespace {

// Runs `apply`, a library Error becoming a usage error.
void as_usage(const std::function<void()>& apply) {
    try {
        apply();
    } catch (const Error& e) {
        throw CLI::ValidationError(e.what());
    }
}

void change_http_settings(const std::function<void(net::HttpSettings&)>& change) {
    net::HttpSettings s = net::HttpClient::shared().settings();
    change(s);
    net::HttpClient::shared().set_settings(s);
}

}  // namespace

void add_remote_options(CLI::App& cmd) {
    const std::string help = "Remote datasets (http/https): on-disk cache of fetched byte ranges in " +
                             net::default_cache_folder().string() + ", e.g. 500M or 4G; 0 turns it off (default 2G)";
    cmd.add_option_function<std::string>(
        "--cache-size",
        [](const std::string& value) {
            as_usage([&] { net::RangeCache::configure({{}, value == "0" ? 0 : parse_bytes(value, "--cache-size")}); });
        },
        help);
    cmd.add_option_function<std::string>(
           "--cacert", [](const std::string& file) { change_http_settings([&](auto& s) { s.ca_file = file; }); },
           "Remote datasets (https): trust the CAs of this PEM file instead of the system's (a private or "
           "proxy CA; env LIDARSCOUT_CACERT)")
        ->envname("LIDARSCOUT_CACERT")
        ->check(CLI::ExistingFile);
    cmd.add_option_function<std::string>(
           "--allow-origins",
           [](const std::string& list) {
               as_usage([&] { net::set_allowed_origins(net::parse_allowed_origins(list)); });
           },
           "Remote datasets: other origins (comma-separated URLs, or *) that a dataset's tile list entries, EPT "
           "nodes and redirects may lead to (default: only the dataset's own; env LIDARSCOUT_ALLOW_ORIGINS)")
        ->envname("LIDARSCOUT_ALLOW_ORIGINS");
    cmd.add_option_function<std::string>(
           "--min-rate",
           [](const std::string& value) {
               as_usage([&] {
                   const std::uint64_t rate = value == "0" ? 0 : parse_bytes(value, "--min-rate");
                   change_http_settings([&](auto& s) { s.min_rate = rate; });
               });
           },
           "Remote datasets: a request fails when its bytes arrive slower than this many per second after 30 s, "
           "e.g. 16K (the default) or 1M; 0 turns the deadline off (env LIDARSCOUT_MIN_RATE)")
        ->envname("LIDARSCOUT_MIN_RATE");
    cmd.add_flag_callback(
        "--requester-pays", [] { net::set_s3_requester_pays(true); },
        "s3:// datasets: the requester pays for the transfer (header x-amz-request-payer: requester; "
        "env AWS_REQUEST_PAYER=requester)");
}

CLI::Validator existing_file_or_url() {
    return CLI::Validator(
        [](std::string& path) { return net::is_url(path) ? std::string() : CLI::ExistingFile(path); }, "FILE or URL");
}

}  // namespace lidarscout::cli
