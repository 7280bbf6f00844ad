// --cache-size: the bound of the on-disk cache of remote byte ranges; --cacert: the CAs to trust.
#include "cli/remote_options.hpp"

#include "cli/size_options.hpp"
#include "core/error.hpp"
#include "net/http_client.hpp"
#include "net/range_cache.hpp"
#include "net/url.hpp"

namespace lidarscout::cli {

void add_remote_options(CLI::App& cmd) {
    const std::string help = "Remote datasets (http/https): on-disk cache of fetched byte ranges in " +
                             net::default_cache_folder().string() + ", e.g. 500M or 4G; 0 turns it off (default 2G)";
    cmd.add_option_function<std::string>(
        "--cache-size",
        [](const std::string& value) {
            try {
                const std::uint64_t bytes = value == "0" ? 0 : parse_bytes(value, "--cache-size");
                net::RangeCache::configure({{}, bytes});
            } catch (const Error& e) {
                throw CLI::ValidationError(e.what());  // reported as a usage error
            }
        },
        help);
    cmd.add_option_function<std::string>(
           "--cacert",
           [](const std::string& file) {
               net::HttpSettings s = net::HttpClient::shared().settings();
               s.ca_file = file;
               net::HttpClient::shared().set_settings(s);
           },
           "Remote datasets (https): trust the CAs of this PEM file instead of the system's (a private or "
           "proxy CA; env LIDARSCOUT_CACERT)")
        ->envname("LIDARSCOUT_CACERT")
        ->check(CLI::ExistingFile);
}

CLI::Validator existing_file_or_url() {
    return CLI::Validator(
        [](std::string& path) { return net::is_url(path) ? std::string() : CLI::ExistingFile(path); }, "FILE or URL");
}

}  // namespace lidarscout::cli
