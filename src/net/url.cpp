// URL helpers: scheme test, credential removal, relative resolution.
#include "net/url.hpp"

#include <algorithm>
#include <cctype>
#include <vector>

#include "core/text.hpp"

namespace lidarscout::net {

namespace {

// Where the authority ("host:port", perhaps with "user@") of `url` ends.
std::size_t authority_end(std::string_view url, std::size_t start) {
    const auto end = url.find_first_of("/?#", start);
    return end == std::string_view::npos ? url.size() : end;
}

// The path "a/b/../c" with its dot segments removed.
std::string remove_dot_segments(std::string_view path) {
    std::vector<std::string_view> out;
    std::size_t i = 0;
    while (i <= path.size()) {
        auto slash = path.find('/', i);
        if (slash == std::string_view::npos) slash = path.size();
        const auto seg = path.substr(i, slash - i);
        if (seg == "..") {
            if (out.size() > 1) out.pop_back();  // never above the root
        } else if (seg != ".") {
            out.push_back(seg);
        }
        i = slash + 1;
    }
    std::string joined;
    for (std::size_t k = 0; k < out.size(); ++k) joined += (k ? "/" : "") + std::string(out[k]);
    const auto last = path.substr(path.rfind('/') + 1);
    if ((last == ".." || last == ".") && !joined.empty()) joined += '/';
    return joined;
}

}  // namespace

std::string url_scheme(std::string_view url) {
    const auto colon = url.find("://");
    if (colon == std::string_view::npos) return {};
    const std::string scheme = ascii_lower(url.substr(0, colon));
    return scheme == "http" || scheme == "https" ? scheme : std::string();
}

bool is_url(std::string_view path) { return !url_scheme(path).empty(); }

std::string redact_url(std::string_view url) {
    if (!is_url(url)) return std::string(url);
    const std::size_t start = url.find("://") + 3;
    const std::size_t end = authority_end(url, start);
    const auto at = url.substr(start, end - start).rfind('@');
    if (at == std::string_view::npos) return std::string(url);
    return std::string(url.substr(0, start)) + std::string(url.substr(start + at + 1));
}

std::string resolve_url(std::string_view base, std::string_view reference) {
    if (is_url(reference)) return std::string(reference);
    const std::size_t scheme_end = base.find("://");
    if (scheme_end == std::string_view::npos) return std::string(reference);
    if (reference.rfind("//", 0) == 0) return std::string(base.substr(0, scheme_end + 1)) + std::string(reference);
    const std::size_t path_start = authority_end(base, scheme_end + 3);
    const std::string origin(base.substr(0, path_start));
    if (!reference.empty() && reference[0] == '/') return origin + remove_dot_segments(reference);
    std::string_view base_path = base.substr(path_start);
    base_path = base_path.substr(0, base_path.find_first_of("?#"));
    const auto folder = base_path.substr(0, base_path.rfind('/') + 1);
    std::string path = std::string(folder.empty() ? "/" : folder) + std::string(reference);
    return origin + remove_dot_segments(path);
}

}  // namespace lidarscout::net
