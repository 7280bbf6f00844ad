// The page's files (web/: index.html and its scripts), read once at start-up into memory: the
// server answers a request for a page file from this table by its exact name and never opens a
// file for a request, so no path a client sends can reach the file system.
#pragma once

#include <map>
#include <string>
#include <vector>

#include "serve/response_cache.hpp"

namespace lidarscout::serve {

struct WebAsset {
    std::string content_type;
    EncodedPtr body;
};

// Where the page's folder is looked for: $LIDARSCOUT_WEB, then web/ beside the program, above it
// (a build folder inside the source tree), under ../share/lidarscout, and in the source tree.
std::vector<std::string> web_candidates();
// The first candidate holding index.html; throws lidarscout::Error naming those tried.
std::string default_web_dir();

// The regular files directly in `dir` whose names are plain ([a-z0-9_.-], not starting with '.')
// and end in .html, .js or .css; symbolic links are left out. Throws lidarscout::Error without
// index.html.
std::map<std::string, WebAsset> read_web_assets(const std::string& dir);

}  // namespace lidarscout::serve
