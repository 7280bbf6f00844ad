// Telling which tile a source names (device and inode, a URL's normal form), and leaving out the
// sources that name a tile again, with one warning.
#include "dataset/source_identity.hpp"

#include <sys/stat.h>

#include <algorithm>
#include <bit>
#include <cctype>
#include <cstdio>
#include <filesystem>
#include <unordered_map>
#include <vector>

#include "core/text.hpp"
#include "core/thread_pool.hpp"
#include "io/file.hpp"
#include "net/url.hpp"

namespace lidarscout::dataset {

namespace {

namespace fs = std::filesystem;

constexpr std::size_t kNamesShown = 5;       // tiles named in the warning; the rest counted
constexpr std::size_t kNameCharacters = 200;  // of each name shown

bool is_unreserved(unsigned char c) { return std::isalnum(c) || c == '-' || c == '.' || c == '_' || c == '~'; }

int hex_value(char c) {
    if (c >= '0' && c <= '9') return c - '0';
    const char lower = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    return lower >= 'a' && lower <= 'f' ? lower - 'a' + 10 : -1;
}

// "%7e%2f" -> "~%2F": unreserved characters decoded, the other encodings' hex digits in upper case.
std::string normalise_percent(std::string_view s) {
    std::string out;
    out.reserve(s.size());
    for (std::size_t i = 0; i < s.size(); ++i) {
        const int high = s[i] == '%' && i + 2 < s.size() ? hex_value(s[i + 1]) : -1;
        const int low = high >= 0 ? hex_value(s[i + 2]) : -1;
        if (low < 0) {
            out += s[i];
            continue;
        }
        const auto c = static_cast<unsigned char>(high * 16 + low);
        if (is_unreserved(c)) {
            out += static_cast<char>(c);
        } else {
            out += '%';
            out += static_cast<char>(std::toupper(static_cast<unsigned char>(s[i + 1])));
            out += static_cast<char>(std::toupper(static_cast<unsigned char>(s[i + 2])));
        }
        i += 2;
    }
    return out;
}

bool default_port(const net::UrlParts& p) {
    return p.port.empty() || (p.scheme == "http" && p.port == "80") || (p.scheme == "https" && p.port == "443");
}

std::string local_identity(const std::string& path) {
    struct stat st {};
    if (::stat(path.c_str(), &st) == 0) {
        return "file:" + std::to_string(st.st_dev) + ":" + std::to_string(st.st_ino);
    }
    std::error_code ec;
    const fs::path absolute = fs::absolute(path, ec);
    return "path:" + (ec ? fs::path(path) : absolute).lexically_normal().string();
}

// `name` cut to kNameCharacters, saying how long it was.
std::string cut(const std::string& name) {
    if (name.size() <= kNameCharacters) return name;
    return name.substr(0, kNameCharacters) + "... (" + std::to_string(name.size()) + " characters)";
}

std::string shown_name(const TileSource& source) {
    return display_text(cut(source.name.empty() ? io::display_path(source.path) : source.name));
}

// "a.laz (3 times), b.laz (2 times) and 4 more tiles": `named` holds how often each tile was named.
std::string list_repeated(const std::vector<std::pair<std::string, std::size_t>>& named) {
    std::string list;
    for (std::size_t i = 0; i < named.size() && i < kNamesShown; ++i) {
        list += (i ? ", " : "") + named[i].first + " (" + std::to_string(named[i].second) + " times)";
    }
    if (named.size() > kNamesShown) list += " and " + std::to_string(named.size() - kNamesShown) + " more tiles";
    return list;
}

// Whether `path` (from its leading '/') has a "." or ".." segment, or an empty one before another. (One pass: a
// find for each spelling, and find_first_of, had been half of a country's duplicate check, 152,100 hrefs.)
bool has_dot_or_empty_segment(std::string_view path) {
    std::size_t start = 1;
    for (std::size_t i = 1; i <= path.size(); ++i) {
        if (i < path.size() && path[i] != '/') continue;
        const std::string_view segment = path.substr(start, i - start);
        if (segment == "." || segment == ".." || (segment.empty() && i < path.size())) return true;
        start = i + 1;
    }
    return false;
}

// True when the http(s) `url` is in its normal form as written (what most of a catalog's thousands of hrefs are):
// scheme and host in lower case, a port other than the default or none, no credentials, fragment or
// percent-encoding, and no "." or ".." segment or empty one in its path. A country's 152,100 items are compared
// without parsing each.
bool already_normal(std::string_view url) {
    const std::size_t scheme = url.starts_with("http://") ? 4 : url.starts_with("https://") ? 5 : 0;
    if (scheme == 0) return false;
    const std::size_t start = scheme + 3;
    std::size_t end = start;
    while (end < url.size() && url[end] != '/' && url[end] != '?' && url[end] != '#') ++end;
    if (end == url.size() || url[end] != '/' || end == start) return false;
    const std::string_view authority = url.substr(start, end - start), rest = url.substr(end);
    const std::size_t colon = authority.find(':');
    const std::string_view host = authority.substr(0, colon);
    const auto host_char = [](char c) {
        return (c >= 'a' && c <= 'z') || (c >= '0' && c <= '9') || c == '.' || c == '-';
    };
    if (host.empty() || !std::all_of(host.begin(), host.end(), host_char)) return false;
    if (colon != std::string_view::npos) {
        const std::string_view port = authority.substr(colon + 1);
        const auto digit = [](char c) { return c >= '0' && c <= '9'; };
        if (port.empty() || !std::all_of(port.begin(), port.end(), digit) || port.front() == '0') return false;
        if (port == (scheme == 4 ? "80" : "443")) return false;
    }
    if (std::any_of(rest.begin(), rest.end(), [](char c) { return c == '%' || c == '#' || c == '\\'; })) return false;
    return !has_dot_or_empty_segment(rest.substr(0, rest.find('?')));
}

constexpr std::size_t kNone = static_cast<std::size_t>(-1);

// The identity of `source` (source_identity) as a view: an http(s) URL already in its normal form (a catalog's
// hrefs, as a rule) is its own path, not copied; another URL's normal form, or any other source's identity, is
// made into `made`. (A bare URL never equals a "file:", "path:" or "url:" identity.)
std::string_view identity_view(const TileSource& source, std::string& made) {
    if (!source.shift && already_normal(source.path)) return source.path;
    made = source.shift || !net::is_url(source.path) ? source_identity(source) : normalised_url(source.path);
    return made;
}

}  // namespace

std::string normalised_url(std::string_view url) {
    if (already_normal(url)) return std::string(url);
    const auto p = net::parse_url(url);
    if (!p) return std::string(url);
    if (p->scheme == "s3") {  // the key as it is requested (a key that leaves its bucket as written: never read)
        std::string refusal;
        const std::string key = net::normalise_s3_key(std::string_view(p->path).substr(p->path.empty() ? 0 : 1), "",
                                                      refusal);
        return "s3://" + p->host + "/" + (refusal.empty() ? key : p->path);
    }
    const std::string origin =
        p->scheme + "://" + ascii_lower(normalise_percent(p->host)) + (default_port(*p) ? "" : ":" + p->port);
    // The path resolved as a relative reference to the origin's root ("." first: a path "//x" is no host).
    const std::string path = normalise_percent(p->path);
    std::string out = net::resolve_url(origin + "/", "." + (path.empty() ? std::string("/") : path));
    if (out.size() == origin.size()) out += '/';  // ("/a/.." leaves no path: the root, as "http://h" is "http://h/")
    if (!p->query.empty()) out += "?" + normalise_percent(p->query);
    return out;
}

std::string source_identity(const TileSource& source) {
    std::string id = net::is_url(source.path) ? "url:" + normalised_url(source.path) : local_identity(source.path);
    if (source.shift) {
        char shift[80];
        std::snprintf(shift, sizeof shift, " shifted %a %a", (*source.shift)[0], (*source.shift)[1]);
        id += shift;
    }
    return id;
}

void drop_duplicate_sources(FoundSources& found) {
    // Each source's identity hashed (in blocks on the shared pool: a local folder's stat each), then kept in an
    // open-addressed table of first sources by hash, its identities compared only where hashes meet. (A map of
    // identities, a node each, had taken 70-90 ms of a country's 152,100 hrefs before its footprints showed.)
    const std::vector<TileSource>& sources = found.sources;
    const std::size_t n = sources.size();
    if (n < 2) return;
    std::vector<std::size_t> hashes(n);
    ThreadPool::shared().for_each_block(n, 2048, [&](std::size_t begin, std::size_t end) {
        std::string made;
        for (std::size_t i = begin; i < end; ++i) {
            hashes[i] = std::hash<std::string_view>{}(identity_view(sources[i], made));
        }
    });
    const std::size_t mask = std::bit_ceil(2 * n) - 1;
    std::vector<std::size_t> first(mask + 1, kNone);  // a slot's first source (kNone: empty)
    std::unordered_map<std::size_t, std::size_t> times;  // first source -> times named, when more than once
    std::vector<std::size_t> repeated;                   // those first sources, in order
    std::vector<bool> dropped(n);
    std::string made_i, made_j;
    for (std::size_t i = 0; i < n; ++i) {
        std::size_t slot = hashes[i] & mask;
        for (; first[slot] != kNone; slot = (slot + 1) & mask) {
            const std::size_t j = first[slot];
            if (hashes[j] != hashes[i] || identity_view(sources[j], made_j) != identity_view(sources[i], made_i)) {
                continue;
            }
            if (times[j]++ == 0) repeated.push_back(j);
            dropped[i] = true;
            break;
        }
        if (!dropped[i]) first[slot] = i;
    }
    if (repeated.empty()) return;
    std::sort(repeated.begin(), repeated.end());
    std::vector<std::pair<std::string, std::size_t>> named;
    for (const std::size_t r : repeated) named.emplace_back(shown_name(found.sources[r]), times[r] + 1);
    std::size_t kept = 0;
    for (std::size_t i = 0; i < n; ++i) {
        if (dropped[i]) continue;
        if (kept != i) found.sources[kept] = std::move(found.sources[i]);
        ++kept;
    }
    found.sources.resize(kept);
    const std::size_t left_out = n - kept;
    found.warnings.warn(std::to_string(left_out) + (left_out == 1 ? " input names a tile" : " inputs name tiles") +
                        " already named, read once: " + list_repeated(named));
}

}  // namespace lidarscout::dataset
