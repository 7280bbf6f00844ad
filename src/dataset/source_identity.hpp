// Which tile a source names, whatever name it is given: so that a tile named by several catalog
// items, tile-list entries or arguments ("a.laz", "./a.laz", "d/../a.laz", a symlink, a hard link;
// "HTTP://Host:80/d/../a.laz" and "http://host/a.laz") is read once, and counted once. A local
// file is known by its device and inode, a URL by its normal form; a virtual replica's tile by its
// source's identity and its shift (the tiles of a replica share one file on purpose, at different
// places).
#pragma once

#include <string>
#include <string_view>

#include "dataset/file_search.hpp"

namespace lidarscout::dataset {

// `url` in a normal form, for comparison only (RFC 3986, 6.2.2): scheme and host in lower case, the
// default port dropped, credentials and fragment dropped, percent-encodings of unreserved characters
// decoded and the others' hex digits in upper case, then "." and ".." segments of the path
// resolved. An s3 URL: its bucket as written (the name is case-sensitive) and its key as it is
// requested (net::normalise_s3_key; otherwise literal: "%41" is not "A" there). Anything not a URL
// as it is. (net/url.hpp has no normaliser of whole URLs; this is the one the dataset needs.)
std::string normalised_url(std::string_view url);

// What names the tile of `source`: "file:DEVICE:INODE" for a local file that exists (stat follows
// links), "path:" and its absolute, lexically normal path for one that does not, "url:" and
// normalised_url for a URL; a virtual replica's tile adds its shift.
std::string source_identity(const TileSource& source);

// Keeps the first source of each tile (source_identity), in order, and says in one warning in
// `found.warnings` how many were left out and which tiles they named (the first few, with how
// many times each was named).
void drop_duplicate_sources(FoundSources& found);

}  // namespace lidarscout::dataset
