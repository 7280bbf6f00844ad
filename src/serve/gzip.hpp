// gzip (zlib, Debian zlib1g-dev) of the API's responses: compressed once when encoded and kept
// so in the cache; inflated again only for a client that does not accept gzip.
#pragma once

#include <string>
#include <string_view>

namespace lidarscout::serve {

// The gzip stream (RFC 1952) of `data`.
std::string gzip(std::string_view data);
// The data of a gzip stream made by gzip(); throws lidarscout::Error when it is not one.
std::string gunzip(std::string_view stream);

}  // namespace lidarscout::serve
