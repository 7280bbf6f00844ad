// XML elements and entities of object store answers.
#include "net/xml_text.hpp"

#include <array>
#include <cstdlib>
#include <utility>

#include "core/text.hpp"

namespace lidarscout::net {

namespace {

// The entity between '&' and ';' decoded into `out`; false when it is not one.
bool decode_entity(std::string_view name, std::string& out) {
    static constexpr std::array<std::pair<std::string_view, char>, 5> kNamed = {
        {{"amp", '&'}, {"lt", '<'}, {"gt", '>'}, {"quot", '"'}, {"apos", '\''}}};
    for (const auto& [n, c] : kNamed) {
        if (name == n) return out += c, true;
    }
    if (name.size() < 2 || name[0] != '#') return false;
    const bool hex = name[1] == 'x' || name[1] == 'X';
    const std::string digits(name.substr(hex ? 2 : 1));
    char* end = nullptr;
    const unsigned long code = std::strtoul(digits.c_str(), &end, hex ? 16 : 10);
    if (digits.empty() || *end != '\0' || code > 0x10FFFF) return false;
    append_utf8(out, code);
    return true;
}

}  // namespace

void for_each_xml_element(std::string_view xml, std::string_view tag,
                          const std::function<bool(std::string_view)>& visit) {
    const std::string open = "<" + std::string(tag) + ">", close = "</" + std::string(tag) + ">";
    std::size_t at = 0;
    for (;;) {
        const auto start = xml.find(open, at);
        if (start == std::string_view::npos) return;
        const auto end = xml.find(close, start + open.size());
        if (end == std::string_view::npos) return;
        if (!visit(xml.substr(start + open.size(), end - start - open.size()))) return;
        at = end + close.size();
    }
}

std::vector<std::string_view> xml_elements(std::string_view xml, std::string_view tag) {
    std::vector<std::string_view> out;
    for_each_xml_element(xml, tag, [&](std::string_view element) { return out.push_back(element), true; });
    return out;
}

std::string xml_text(std::string_view xml, std::string_view tag) {
    std::string text;
    for_each_xml_element(xml, tag, [&](std::string_view element) { return text = xml_decode(element), false; });
    return text;
}

std::string xml_decode(std::string_view text) {
    std::string out;
    out.reserve(text.size());
    for (std::size_t i = 0; i < text.size(); ++i) {
        const auto semicolon = text[i] == '&' ? text.find(';', i) : std::string_view::npos;
        if (semicolon != std::string_view::npos && semicolon - i <= 10 &&
            decode_entity(text.substr(i + 1, semicolon - i - 1), out)) {
            i = semicolon;
            continue;
        }
        out += text[i];
    }
    return out;
}

}  // namespace lidarscout::net
