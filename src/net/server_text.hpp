// Text a server sent, made fit to show: an S3 error's code, message, region and endpoint, an
// echoed header (Content-Range, ETag, Location), a listed key. A hostile or careless server may
// echo the credentials it was sent (the session token of a signed request in its error body), so
// every such text passes through server_text(): each credential the process uses (remembered
// here by net/s3_config.cpp when a configuration is read or set), and every piece of one of 12
// characters or more, is replaced by "[redacted]", control characters are escaped (one line),
// and the text is cut to at most kServerTextMax characters, naming its full length.
#pragma once

#include <cstddef>
#include <string>
#include <string_view>

namespace lidarscout::net {

constexpr std::size_t kServerTextMax = 200;

// Remembers a credential in use (an access key id, a secret, a session token) for the
// redaction; values shorter than 4 characters are not secrets and are ignored.
void remember_secret(std::string_view secret);

// `text` with every remembered credential, and every piece of 12 characters or more of one,
// replaced by "[redacted]".
std::string redact_secrets(std::string_view text);

// `text` (from a server) redacted, its control characters escaped and cut to `max` characters
// ("...", then its full length in bytes, when cut).
std::string server_text(std::string_view text, std::size_t max = kServerTextMax);

}  // namespace lidarscout::net
