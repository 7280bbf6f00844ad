// URLs as paths: telling an http(s) URL from a file path, removing the credentials a URL
// may carry before it is shown anywhere, and resolving a relative URL against the URL of
// the list that names it.
#pragma once

#include <string>
#include <string_view>

namespace lidarscout::net {

// True for "http://..." and "https://..." (scheme case-insensitive).
bool is_url(std::string_view path);

// The URL without "user:password@" (the form shown to users, in errors and in JSON).
std::string redact_url(std::string_view url);

// The scheme in lower case ("http" or "https"); empty when `url` is not one.
std::string url_scheme(std::string_view url);

// `reference` resolved against `base` (RFC 3986 in its common forms): an absolute URL as
// is, "//host/x" with base's scheme, "/x" from base's host, anything else relative to the
// folder of base's path ("../" and "./" segments removed). Query and fragment of base dropped.
std::string resolve_url(std::string_view base, std::string_view reference);

}  // namespace lidarscout::net
