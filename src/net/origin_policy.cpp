// The origins a dataset's derived URLs may use: the process's setting and the check.
#include "net/origin_policy.hpp"

#include <algorithm>
#include <mutex>

#include "core/error.hpp"
#include "net/s3_request.hpp"
#include "net/url.hpp"

namespace lidarscout::net {

namespace {

struct Setting {
    std::mutex mutex;
    AllowedOrigins allowed;
};

Setting& setting() {
    static Setting s;
    return s;
}

}  // namespace

AllowedOrigins parse_allowed_origins(std::string_view list) {
    AllowedOrigins out;
    std::size_t i = 0;
    while (i <= list.size()) {
        auto comma = list.find(',', i);
        if (comma == std::string_view::npos) comma = list.size();
        const std::string item(list.substr(i, comma - i));
        i = comma + 1;
        if (item.empty()) continue;
        if (item == "*") {
            out.any = true;
            continue;
        }
        const std::string origin = url_origin(item);
        if (origin.empty() || !url_problem(item).empty()) {
            throw Error("--allow-origins: \"" + redact_url(item) + "\" is not an http(s) URL (or \"*\")");
        }
        out.origins.push_back(origin);
    }
    return out;
}

void set_allowed_origins(AllowedOrigins allowed) {
    std::lock_guard lock(setting().mutex);
    setting().allowed = std::move(allowed);
}

AllowedOrigins allowed_origins() {
    std::lock_guard lock(setting().mutex);
    return setting().allowed;
}

std::string derived_url_refusal(std::string_view base, std::string_view derived) {
    const std::string from = url_scheme(base), to = url_scheme(derived);
    if (to.empty()) return "\"" + redact_url(derived) + "\" is not an http(s) URL";
    if (from == "https" && to == "http") return "a downgrade from https to http is refused";
    if (to == "s3") {  // (its origin is its bucket: the key must stay inside it, however spelled)
        std::string refusal;
        if (const auto where = parse_s3_url(derived)) normalise_s3_key(where->key, {}, refusal);
        if (!refusal.empty()) return "its key " + refusal;
    }
    const std::string origin = url_origin(derived);
    if (origin == url_origin(base)) return {};
    const AllowedOrigins allowed = allowed_origins();
    if (allowed.any || std::find(allowed.origins.begin(), allowed.origins.end(), origin) != allowed.origins.end()) {
        return {};
    }
    return "it leads to " + origin + ", another origin than the dataset's " + url_origin(base) +
           " (allow it with --allow-origins)";
}

}  // namespace lidarscout::net
