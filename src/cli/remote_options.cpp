// --cache-size: the bound of the on-disk cache of remote byte ranges; --cacert: the CAs to trust;
// --allow-origins: other origins a dataset's URLs may lead to; --min-rate: the request deadline;
// --requester-pays: s3 requests that the requester pays for; --merge-gap: how far apart the ranges of
// one read may lie and still go as one range to a server that answers one range per request.
#include "cli/remote_options.hpp"

#include <functional>
#include <string>

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

// An option of a byte count (parse_bytes, or 0) that sets `field` of the HTTP client's settings.
CLI::Option* add_byte_setting(CLI::App& cmd, const std::string& name, std::uint64_t net::HttpSettings::*field,
                              const std::string& help) {
    return cmd.add_option_function<std::string>(
        name,
        [name, field](const std::string& value) {
            as_usage([&] {
                const std::uint64_t bytes = value == "0" ? 0 : parse_bytes(value, name.c_str());
                change_http_settings([&](auto& s) { s.*field = bytes; });
            });
        },
        help);
}

}  // namespace

void add_remote_options(CLI::App& cmd) {
    const std::string help = "Remote datasets (http/https): on-disk cache of fetched byte ranges in " +
                             net::default_cache_folder().string() +
                             " (and, apart, of `view`'s overview sidecars: --cache), e.g. 500M or 4G; 0 turns it off "
                             "(default 2G)";
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
    add_byte_setting(cmd, "--min-rate", &net::HttpSettings::min_rate,
                     "Remote datasets: a request fails when its bytes arrive slower than this many per second after "
                     "30 s, e.g. 16K (the default) or 1M; 0 turns the deadline off (env LIDARSCOUT_MIN_RATE)")
        ->envname("LIDARSCOUT_MIN_RATE");
    add_byte_setting(cmd, "--merge-gap", &net::HttpSettings::merge_gap_one_range,
                     "Remote datasets on servers that answer one range per request (s3://): reads of one file at "
                     "most this many bytes apart go as one request, e.g. 0 or 256K (default " +
                         std::to_string(net::HttpSettings{}.merge_gap_one_range / 1024) +
                         "K: a request more costs about what these bytes do; env LIDARSCOUT_MERGE_GAP)")
        ->envname("LIDARSCOUT_MERGE_GAP");
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
