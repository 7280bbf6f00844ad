// Parsing of --listen and the loopback and token rules of `lidarscout serve`.
#include "serve/listen_address.hpp"

#include <arpa/inet.h>

#include <charconv>

#include "core/error.hpp"

namespace lidarscout::serve {
namespace {

Error bad_listen(std::string_view text, const std::string& why) {
    return Error("bad --listen '" + std::string(text.substr(0, 80)) + "': " + why +
                 " (HOST:PORT, e.g. 127.0.0.1:8080)");
}

int parse_port(std::string_view text, std::string_view whole) {
    int port = -1;
    const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), port);
    if (text.empty() || ec != std::errc() || end != text.data() + text.size() || port < 0 || port > 65535) {
        throw bad_listen(whole, "the port must be a number within 0-65535");
    }
    return port;
}

bool valid_host(const std::string& host) {
    in_addr v4{};
    in6_addr v6{};
    return host == "localhost" || inet_pton(AF_INET, host.c_str(), &v4) == 1 ||
           inet_pton(AF_INET6, host.c_str(), &v6) == 1;
}

bool url_safe(char c) {
    return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') || c == '-' || c == '_' ||
           c == '.' || c == '~';
}

}  // namespace

ListenAddress parse_listen_address(std::string_view text) {
    const std::size_t colon = text.rfind(':');
    if (colon == std::string_view::npos) throw bad_listen(text, "no port");
    ListenAddress a;
    std::string_view host = text.substr(0, colon);
    if (host.size() >= 2 && host.front() == '[' && host.back() == ']') host = host.substr(1, host.size() - 2);
    if (!host.empty()) a.host = std::string(host);
    a.port = parse_port(text.substr(colon + 1), text);
    if (!valid_host(a.host)) throw bad_listen(text, "the host must be a numeric IPv4 or IPv6 address or localhost");
    return a;
}

bool is_loopback(std::string_view host) {
    if (host == "localhost" || host == "::1") return true;
    in_addr v4{};
    if (inet_pton(AF_INET, std::string(host).c_str(), &v4) != 1) return false;
    return (ntohl(v4.s_addr) >> 24) == 127;
}

void check_access_rule(const ListenAddress& address, const std::string& token) {
    if (token.empty() && !is_loopback(address.host)) {
        throw Error("serve: listening on " + address.host +
                    " (not loopback) needs --token: anyone who can reach the address could read the data");
    }
    if (token.empty()) return;
    if (token.size() < 8) throw Error("serve: --token must have at least 8 characters");
    for (const char c : token) {
        if (!url_safe(c)) throw Error("serve: --token may hold only letters, digits and - _ . ~");
    }
}

bool same_token(std::string_view given, std::string_view expected) {
    unsigned char diff = given.size() == expected.size() ? 0 : 1;
    for (std::size_t i = 0; i < expected.size(); ++i) {
        diff |= static_cast<unsigned char>(expected[i] ^ (i < given.size() ? given[i] : 0));
    }
    return diff == 0;
}

}  // namespace lidarscout::serve
