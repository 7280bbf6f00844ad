// Which URLs a dataset may lead to. Every URL derived from a dataset (an EPT or Entwine node,
// a tile list's entry, a redirect) keeps the scheme and origin (scheme, host, port) of the
// URL it was derived from, unless the user allowed other origins (--allow-origins); a
// downgrade from https to http is refused whatever is allowed. So a hostile list or
// hierarchy cannot send requests (and the credentials or cookies a URL carries) elsewhere.
#pragma once

#include <string>
#include <string_view>
#include <vector>

namespace lidarscout::net {

struct AllowedOrigins {
    bool any = false;                  // every origin ("*")
    std::vector<std::string> origins;  // as url_origin() writes them
};

// "*" or a comma-separated list of URLs ("https://cdn.example.com,http://host:8080");
// throws Error naming an entry that is not an http(s) URL.
AllowedOrigins parse_allowed_origins(std::string_view list);

// The process's setting (none by default).
void set_allowed_origins(AllowedOrigins allowed);
AllowedOrigins allowed_origins();

// Why `derived` may not be read for the dataset at `base` (both http(s) or s3 URLs; an s3
// URL's origin is its bucket), or "" when it may: another scheme or origin than base's (not
// allowed), http after https, or an s3 key that leaves its bucket ("s3://b/../c/x", however
// spelled: net/url.hpp's normalise_s3_key).
std::string derived_url_refusal(std::string_view base, std::string_view derived);

}  // namespace lidarscout::net
