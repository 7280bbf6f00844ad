// URL helpers: scheme test, parsing, credential removal, relative resolution.
#include "net/url.hpp"

#include <algorithm>
#include <array>
#include <cctype>
#include <vector>

#include "core/text.hpp"
#include "net/xml_text.hpp"

namespace lidarscout::net {

namespace {

// Where the authority ("host:port", perhaps with "user@") of `url` ends.
std::size_t authority_end(std::string_view url, std::size_t start) {
    const auto end = url.find_first_of("/?#", start);
    return end == std::string_view::npos ? url.size() : end;
}

std::size_t authority_start(std::string_view url) { return url.find("://") + 3; }

// The port of "host:port" ("" when none), "[v6]:port" included.
std::string_view port_of(std::string_view host_port) {
    const std::size_t after_host = host_port.empty() || host_port[0] != '[' ? 0 : host_port.find(']');
    if (after_host == std::string_view::npos) return {};
    const auto colon = host_port.find(':', after_host);
    return colon == std::string_view::npos ? std::string_view() : host_port.substr(colon + 1);
}

bool all_digits(std::string_view s) {
    return std::all_of(s.begin(), s.end(), [](unsigned char c) { return std::isdigit(c); });
}

// Whether credentials were cut short by an unencoded delimiter: the authority holds no '@',
// but its "port" is not a number, or an '@' follows in a query/fragment before any '/', or in
// a first path segment after a ':'. Then `at` is that '@'.
bool cut_credentials(std::string_view url, std::size_t start, std::size_t end, std::size_t& at) {
    at = url.find('@', end);
    if (at == std::string_view::npos) return false;
    if (!all_digits(port_of(url.substr(start, end - start)))) return true;
    if (end == url.size()) return false;
    if (url[end] == '?' || url[end] == '#') return url.find('/', end) > at;
    const auto segment_end = std::min(url.find_first_of("/?#", end + 1), url.size());
    const auto colon = url.find(':', end);
    return at < segment_end && colon < at;
}

// Where the credentials of `url` end (their '@'), also when unencoded delimiters cut them
// short (then `cut` is set); npos when it has none.
std::size_t credentials_at(std::string_view url, bool& cut) {
    cut = false;
    const std::size_t start = authority_start(url), end = authority_end(url, start);
    const auto at = url.substr(start, end - start).rfind('@');
    if (at != std::string_view::npos) return start + at;
    std::size_t cut_at = 0;
    cut = cut_credentials(url, start, end, cut_at);
    if (!cut) return std::string_view::npos;
    // (the last '@' before the host's path, should the password hold an '@' too)
    const auto path = std::min(url.find_first_of("/?#", cut_at), url.size());
    return url.substr(0, path).rfind('@');
}

// Whether a query parameter of this name carries a credential.
bool is_secret_parameter(std::string_view name) {
    const std::string n = ascii_lower(name);
    static constexpr std::array<std::string_view, 9> kParts = {
        "signature", "token", "secret", "password", "passwd", "credential", "accesskey", "apikey", "api_key"};
    static constexpr std::array<std::string_view, 5> kNames = {"sig", "key", "auth", "authorization", "pwd"};
    return std::any_of(kParts.begin(), kParts.end(), [&](auto p) { return n.find(p) != std::string::npos; }) ||
           std::find(kNames.begin(), kNames.end(), n) != kNames.end();
}

// "a=1&sig=2" with the values of credential parameters replaced.
std::string redact_parameters(std::string_view params) {
    std::string out;
    std::size_t i = 0;
    while (i <= params.size()) {
        auto amp = params.find('&', i);
        if (amp == std::string_view::npos) amp = params.size();
        const auto item = params.substr(i, amp - i);
        const auto eq = item.find('=');
        const bool secret = eq != std::string_view::npos && is_secret_parameter(item.substr(0, eq));
        out += secret ? std::string(item.substr(0, eq)) + "=REDACTED" : std::string(item);
        if (amp < params.size()) out += '&';
        i = amp + 1;
    }
    return out;
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

// `s` with its "%XX" escapes decoded (a '%' not followed by two hex digits kept).
std::string percent_decode(std::string_view s) {
    std::string out;
    out.reserve(s.size());
    const auto hex = [](char c) {
        return std::isdigit(static_cast<unsigned char>(c)) ? c - '0' : (c | 0x20) - 'a' + 10;
    };
    for (std::size_t i = 0; i < s.size(); ++i) {
        if (s[i] == '%' && i + 2 < s.size() && std::isxdigit(static_cast<unsigned char>(s[i + 1])) &&
            std::isxdigit(static_cast<unsigned char>(s[i + 2]))) {
            out += static_cast<char>(hex(s[i + 1]) * 16 + hex(s[i + 2]));
            i += 2;
        } else {
            out += s[i];
        }
    }
    return out;
}

// `text` as a server that decodes too much may read it: escapes and references decoded until
// nothing changes (at most 4 times), '\' as '/'.
std::string fully_decoded(std::string_view text) {
    std::string out(text);
    for (int round = 0; round < 4; ++round) {
        std::string next = percent_decode(xml_decode(out));
        if (next == out) break;
        out = std::move(next);
    }
    std::replace(out.begin(), out.end(), '\\', '/');
    return out;
}

// The '/'-separated `path` with its "." and ".." segments resolved (each segment judged as it is
// written, or fully decoded when `decode_each`); false when a ".." goes above its start.
bool resolve_key_segments(std::string_view path, bool decode_each, std::string& out) {
    std::vector<std::string_view> kept;
    bool last_dot = false;
    for (std::size_t i = 0; i <= path.size();) {
        const auto slash = std::min(path.find('/', i), path.size());
        const auto segment = path.substr(i, slash - i);
        const std::string judged = decode_each ? fully_decoded(segment) : std::string(segment);
        last_dot = judged == "." || judged == "..";
        if (judged == "..") {
            if (kept.empty()) return false;
            kept.pop_back();
        } else if (judged != ".") {
            kept.push_back(segment);
        }
        i = slash + 1;
    }
    out.clear();
    for (std::size_t k = 0; k < kept.size(); ++k) (out += k ? "/" : "") += kept[k];
    if (last_dot && !out.empty()) out += '/';
    return true;
}

// The key as requested and as read fully decoded, or false when either leaves the bucket.
bool key_forms(std::string_view key, std::string& written, std::string& decoded) {
    if (key.find_first_of("%&\\") == std::string_view::npos) {  // (nothing to decode: one form)
        if (!resolve_key_segments(key, false, written)) return false;
        decoded = written;
        return true;
    }
    return resolve_key_segments(key, true, written) && resolve_key_segments(fully_decoded(key), false, decoded);
}

}  // namespace

std::string normalise_s3_key(std::string_view key, std::string_view prefix, std::string& refusal) {
    refusal.clear();
    if (key.size() > kMaxS3Key) {
        refusal = "is longer than S3's " + std::to_string(kMaxS3Key) + " bytes (" + std::to_string(key.size()) + ")";
        return {};
    }
    std::string written, decoded, prefix_written, prefix_decoded;
    if (!key_forms(key, written, decoded)) {
        refusal = "leaves its bucket (a \"..\" segment above the bucket's root)";
        return {};
    }
    if (!prefix.empty() && (!key_forms(prefix, prefix_written, prefix_decoded) ||
                            written.rfind(prefix_written, 0) != 0 || decoded.rfind(prefix_decoded, 0) != 0)) {
        refusal = "leaves the prefix listed (\"" + std::string(prefix) + "\")";
        return {};
    }
    return written;
}

std::string url_scheme(std::string_view url) {
    const auto colon = url.find("://");
    if (colon == std::string_view::npos) return {};
    const std::string scheme = ascii_lower(url.substr(0, colon));
    return scheme == "http" || scheme == "https" || scheme == "s3" ? scheme : std::string();
}

bool is_url(std::string_view path) { return !url_scheme(path).empty(); }

std::optional<UrlParts> parse_url(std::string_view url) {
    UrlParts p;
    p.scheme = url_scheme(url);
    if (p.scheme.empty()) return std::nullopt;
    const std::size_t start = authority_start(url), end = authority_end(url, start);
    std::string_view authority = url.substr(start, end - start);
    if (const auto at = authority.rfind('@'); at != std::string_view::npos) {
        p.userinfo = std::string(authority.substr(0, at));
        authority.remove_prefix(at + 1);
    }
    p.port = std::string(port_of(authority));
    p.host = std::string(authority.substr(0, p.port.empty() ? authority.size() : authority.size() - p.port.size() - 1));
    if (!p.host.empty() && p.host.back() == ':') p.host.pop_back();  // "host:" (an empty port)
    std::string_view rest = url.substr(end);
    const auto hash = rest.find('#');
    if (hash != std::string_view::npos) p.fragment = std::string(rest.substr(hash + 1));
    rest = rest.substr(0, hash);
    const auto question = rest.find('?');
    if (question != std::string_view::npos) p.query = std::string(rest.substr(question + 1));
    p.path = std::string(rest.substr(0, question));
    return p;
}

std::string url_problem(std::string_view url) {
    if (!is_url(url)) return {};
    bool cut = false;
    credentials_at(url, cut);
    if (cut) {
        return "the URL's user:password part holds an unencoded '#', '?' or '/'; percent-encode them "
               "(%23, %3F, %2F)";
    }
    const std::size_t start = authority_start(url), end = authority_end(url, start);
    const auto authority = url.substr(start, end - start);
    const auto port = port_of(authority.substr(authority.rfind('@') + 1));
    if (!all_digits(port)) return "the URL's port \"" + std::string(port) + "\" is not a number";
    return {};
}

std::string redact_url(std::string_view url) {
    if (!is_url(url)) return std::string(url);
    bool cut = false;
    const std::size_t at = credentials_at(url, cut);
    const std::size_t start = authority_start(url);
    const std::string plain = at == std::string_view::npos
                                  ? std::string(url)
                                  : std::string(url.substr(0, start)) + std::string(url.substr(at + 1));
    const std::size_t end = authority_end(plain, authority_start(plain));
    std::string_view rest = std::string_view(plain).substr(end);
    const auto hash = rest.find('#');
    const auto question = rest.substr(0, hash).find('?');
    std::string out = plain.substr(0, end) + std::string(rest.substr(0, std::min(question, hash)));
    if (question != std::string_view::npos) {
        const auto query_end = hash == std::string_view::npos ? rest.size() : hash;
        out += "?" + redact_parameters(rest.substr(question + 1, query_end - question - 1));
    }
    if (hash != std::string_view::npos) out += "#" + redact_parameters(rest.substr(hash + 1));
    return out;
}

std::string url_origin(std::string_view url) {
    const auto p = parse_url(url);
    if (!p) return {};
    if (p->scheme == "s3") return "s3://" + p->host;  // a bucket
    const std::string port = p->port.empty() ? (p->scheme == "https" ? "443" : "80") : p->port;
    return p->scheme + "://" + ascii_lower(p->host) + ":" + port;
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

std::optional<std::string> plain_reference_prefix(std::string_view base) {
    const std::string scheme = url_scheme(base);
    if (scheme != "http" && scheme != "https") return std::nullopt;
    std::string prefix = resolve_url(base, "x");  // (the folder as resolve_url makes it, whatever base's spelling)
    if (!prefix.ends_with("/x") || url_origin(prefix) != url_origin(base)) return std::nullopt;
    prefix.pop_back();
    return prefix;
}

}  // namespace lidarscout::net
