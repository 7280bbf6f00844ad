// display_text: UTF-8 where valid, else Latin-1, control characters escaped; display_excerpt: its cut
// form; count_text.
#include "core/text.hpp"

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <iterator>

namespace lidarscout {
namespace {

// Length of the valid UTF-8 sequence starting at `at` (0 when it is not one): no overlong
// forms, no surrogates, nothing above U+10FFFF.
std::size_t utf8_sequence(std::string_view s, std::size_t at, std::uint32_t& code) {
    const auto byte = [&](std::size_t i) { return static_cast<std::uint8_t>(s[i]); };
    const std::uint8_t b0 = byte(at);
    std::size_t n = 0;
    if (b0 >= 0xC2 && b0 <= 0xDF) {
        n = 2, code = b0 & 0x1F;
    } else if (b0 >= 0xE0 && b0 <= 0xEF) {
        n = 3, code = b0 & 0x0F;
    } else if (b0 >= 0xF0 && b0 <= 0xF4) {
        n = 4, code = b0 & 0x07;
    } else {
        return 0;
    }
    if (at + n > s.size()) return 0;
    for (std::size_t i = 1; i < n; ++i) {
        if ((byte(at + i) & 0xC0) != 0x80) return 0;
        code = (code << 6) | (byte(at + i) & 0x3F);
    }
    const bool overlong = (n == 3 && code < 0x800) || (n == 4 && code < 0x10000);
    const bool invalid = (code >= 0xD800 && code <= 0xDFFF) || code > 0x10FFFF;
    return overlong || invalid ? 0 : n;
}

void escape(std::string& out, unsigned value) {
    char buf[8];
    std::snprintf(buf, sizeof buf, "\\x%02X", value & 0xFFu);
    out += buf;
}

bool is_control(std::uint32_t code) { return code < 0x20 || code == 0x7F || (code >= 0x80 && code <= 0x9F); }

}  // namespace

std::string display_text(std::string_view bytes) {
    std::string out;
    out.reserve(bytes.size());
    for (std::size_t i = 0; i < bytes.size();) {
        const auto b = static_cast<std::uint8_t>(bytes[i]);
        std::uint32_t code = b;
        const std::size_t n = b < 0x80 ? 1 : utf8_sequence(bytes, i, code);
        if (n == 0) {  // not UTF-8 here: the byte is a Latin-1 character
            if (is_control(b)) {
                escape(out, b);
            } else {
                out += static_cast<char>(0xC0 | (b >> 6));
                out += static_cast<char>(0x80 | (b & 0x3F));
            }
            ++i;
            continue;
        }
        if (is_control(code)) {
            escape(out, code);
        } else {
            out.append(bytes.substr(i, n));
        }
        i += n;
    }
    return out;
}

std::string display_excerpt(std::string_view bytes, std::size_t max_bytes) {
    if (bytes.size() <= max_bytes) return display_text(bytes);
    std::size_t cut = max_bytes;
    // back to the start of a UTF-8 sequence (at most 3 continuation bytes), so no character is split
    for (int k = 0; k < 3 && cut > 0 && (static_cast<std::uint8_t>(bytes[cut]) & 0xC0) == 0x80; ++k) --cut;
    return display_text(bytes.substr(0, cut)) + "... (" + std::to_string(bytes.size()) + " bytes)";
}

std::string ascii_lower(std::string_view s) {
    std::string out(s);
    for (char& c : out) {
        if (c >= 'A' && c <= 'Z') c = static_cast<char>(c - 'A' + 'a');
    }
    return out;
}

std::string count_text(double count) {
    if (std::isnan(count)) return "?";
    if (count < 0) return "-" + count_text(-count);
    char text[32];
    if (std::round(count) < 1000) {
        std::snprintf(text, sizeof text, "%.0f", count);
        return text;
    }
    static constexpr const char* kUnits[] = {"k", "M", "G", "T"};
    double value = count / 1e3;
    std::size_t unit = 0;
    // Past 999.5 a unit shows as 1000 at three digits: the next unit then ("1.00 M", not "1000 k").
    while (unit + 1 < std::size(kUnits) && value >= 999.5) value /= 1e3, ++unit;
    const int decimals = value < 9.995 ? 2 : value < 99.95 ? 1 : 0;
    std::snprintf(text, sizeof text, "%.*f %s", decimals, value, kUnits[unit]);
    return text;
}

void append_utf8(std::string& out, unsigned long code) {
    if (code < 0x80) {
        out += static_cast<char>(code);
    } else if (code < 0x800) {
        out += static_cast<char>(0xC0 | (code >> 6));
        out += static_cast<char>(0x80 | (code & 0x3F));
    } else if (code < 0x10000) {
        out += static_cast<char>(0xE0 | (code >> 12));
        out += static_cast<char>(0x80 | ((code >> 6) & 0x3F));
        out += static_cast<char>(0x80 | (code & 0x3F));
    } else {
        out += static_cast<char>(0xF0 | (code >> 18));
        out += static_cast<char>(0x80 | ((code >> 12) & 0x3F));
        out += static_cast<char>(0x80 | ((code >> 6) & 0x3F));
        out += static_cast<char>(0x80 | (code & 0x3F));
    }
}

}  // namespace lidarscout
