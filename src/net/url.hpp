// URLs as paths: telling an http(s) or s3 URL from a file path, parsing one into its parts (RFC
// 3986's generic syntax), removing the secrets a URL may carry (its "user:password@" and
// query parameters that are credentials: signed S3, GCS and Azure URLs, tokens, keys) before
// it is shown anywhere, refusing one whose credentials hold unencoded delimiters, and
// resolving a relative URL against the URL of the list or dataset that names it; an S3 key
// normalised and kept inside its bucket.
#pragma once

#include <optional>
#include <string>
#include <string_view>

namespace lidarscout::net {

// True for "http://...", "https://..." and "s3://bucket/key" (scheme case-insensitive).
bool is_url(std::string_view path);

// The parts of an http(s) URL "scheme://userinfo@host:port/path?query#fragment", as written
// (of an s3 URL: the bucket as host, "/key" as path).
struct UrlParts {
    std::string scheme;              // lower case
    std::optional<std::string> userinfo;
    std::string host;                // "[...]" kept for IPv6
    std::string port;                // "" when none
    std::string path, query, fragment;  // path with its leading '/'; query and fragment without '?' / '#'
};
// The parts of `url`, or nothing when it is not an http(s) URL.
std::optional<UrlParts> parse_url(std::string_view url);

// Why `url` cannot be used as it is written, or "" when it can: credentials holding an
// unencoded '#', '?' or '/' (which would end them early and send the rest of the password
// elsewhere), or a port that is not a number.
std::string url_problem(std::string_view url);

// The URL as shown to users, in errors, logs and JSON: without "user:password@" and with the
// values of credential query parameters (X-Amz-Signature, X-Amz-Credential,
// X-Amz-Security-Token, X-Goog-Signature, sig, token, key, signature, access_token, ...)
// replaced by "REDACTED". Anything that is not a URL is returned as it is.
std::string redact_url(std::string_view url);

// The scheme in lower case ("http", "https" or "s3"); empty when `url` is not one.
std::string url_scheme(std::string_view url);

// "scheme://host:port" of `url`, scheme and host in lower case, the port always given (80
// and 443 by default); "s3://bucket" for an s3 URL (the bucket as written: its name is
// case-sensitive); empty when `url` is not a URL.
std::string url_origin(std::string_view url);

// The most bytes of an S3 key (S3's own limit).
constexpr std::size_t kMaxS3Key = 1024;

// The S3 key `key` as it is requested: its "." and ".." segments removed ("a/./b/../c" is
// "a/c"), also those spelled with percent-escapes or XML character references ("%2e%2e",
// "&#46;&#46;"). `refusal` says why it may not be requested ("" when it may), to follow "the
// key": "is longer than" kMaxS3Key bytes, or "leaves its bucket" or `prefix` (given as written;
// "" for the whole bucket), either as written or read the way a server that decodes too much would read it
// (every escape and reference decoded, repeatedly, and '\' taken as '/').
std::string normalise_s3_key(std::string_view key, std::string_view prefix, std::string& refusal);

// `reference` resolved against `base` (RFC 3986 in its common forms): an absolute URL as
// is, "//host/x" with base's scheme, "/x" from base's host, anything else relative to the
// folder of base's path ("../" and "./" segments removed). Query and fragment of base dropped.
std::string resolve_url(std::string_view base, std::string_view reference);

// What a plain relative reference (segments none of them empty, "." or "..", a leading "./" aside) resolved
// against the http(s) URL `base` starts with: resolve_url(base, ref) is it followed by ref (less a leading
// "./"), on base's origin. nullopt for another base. (A catalog's 152,100 item hrefs were resolved one by one.)
std::optional<std::string> plain_reference_prefix(std::string_view base);

}  // namespace lidarscout::net
