// Where `lidarscout serve` listens and who may ask it: HOST:PORT parsed strictly, whether the
// host is a loopback address (the default, 127.0.0.1:0), and the rule that any other address
// needs a token. A token is compared in constant time.
#pragma once

#include <string>
#include <string_view>

namespace lidarscout::serve {

struct ListenAddress {
    std::string host = "127.0.0.1";
    int port = 0;  // 0: the system picks a free port
};

// "HOST:PORT", "[IPV6]:PORT" or ":PORT" (loopback); throws lidarscout::Error naming --listen.
ListenAddress parse_listen_address(std::string_view text);

// 127.0.0.0/8, ::1 and "localhost".
bool is_loopback(std::string_view host);

// Throws lidarscout::Error (one line) when `address` is not loopback and `token` is empty, or
// when a token is too short to guess at (fewer than 8 characters) or holds characters a URL would
// have to encode.
void check_access_rule(const ListenAddress& address, const std::string& token);

// Equal, in time independent of where they differ.
bool same_token(std::string_view given, std::string_view expected);

}  // namespace lidarscout::serve
