// Range / Content-Range headers and the multipart/byteranges parser.
#include "net/byte_ranges.hpp"

#include <algorithm>
#include <cctype>
#include <charconv>

#include "core/error.hpp"

namespace lidarscout::net {

namespace {

std::string_view trim(std::string_view s) {
    while (!s.empty() && (s.front() == ' ' || s.front() == '\t')) s.remove_prefix(1);
    while (!s.empty() && (s.back() == ' ' || s.back() == '\t' || s.back() == '\r')) s.remove_suffix(1);
    return s;
}

bool iequals_prefix(std::string_view s, std::string_view prefix) {
    if (s.size() < prefix.size()) return false;
    for (std::size_t i = 0; i < prefix.size(); ++i) {
        if (std::tolower(static_cast<unsigned char>(s[i])) != std::tolower(static_cast<unsigned char>(prefix[i]))) {
            return false;
        }
    }
    return true;
}

// A whole decimal number (no sign, no spaces).
std::optional<std::uint64_t> parse_number(std::string_view s) {
    std::uint64_t v = 0;
    if (s.empty()) return std::nullopt;
    const auto [end, ec] = std::from_chars(s.data(), s.data() + s.size(), v);
    if (ec != std::errc() || end != s.data() + s.size()) return std::nullopt;
    return v;
}

[[noreturn]] void malformed(const std::string& what) {
    throw Error("malformed multipart/byteranges response: " + what);
}

// Reads the multipart body from a cursor: `at` moves forward as parts are consumed.
class Cursor {
public:
    explicit Cursor(std::span<const std::uint8_t> body) : body_(body) {}
    bool starts_with(std::string_view s) const {
        return body_.size() - at_ >= s.size() && std::equal(s.begin(), s.end(), body_.begin() + at_);
    }
    void expect(std::string_view s, const char* what) {
        if (!starts_with(s)) malformed(std::string("expected ") + what + " at byte " + std::to_string(at_));
        at_ += s.size();
    }
    void skip_crlf() {
        while (starts_with("\r\n")) at_ += 2;
    }
    // One header line (without its CRLF); empty at the blank line ending the headers.
    std::string_view line() {
        const auto* begin = reinterpret_cast<const char*>(body_.data()) + at_;
        const std::string_view rest(begin, body_.size() - at_);
        const auto end = rest.find("\r\n");
        if (end == std::string_view::npos) malformed("a part's headers do not end");
        at_ += end + 2;
        return rest.substr(0, end);
    }
    std::span<const std::uint8_t> take(std::uint64_t n) {
        if (n > body_.size() - at_) malformed("a part is shorter than its Content-Range");
        const auto out = body_.subspan(at_, static_cast<std::size_t>(n));
        at_ += static_cast<std::size_t>(n);
        return out;
    }

private:
    std::span<const std::uint8_t> body_;
    std::size_t at_ = 0;
};

ContentRange read_part_headers(Cursor& c) {
    std::optional<ContentRange> range;
    for (std::string_view l = c.line(); !l.empty(); l = c.line()) {
        if (!iequals_prefix(l, "content-range:")) continue;
        range = parse_content_range(l.substr(14));
        if (!range) malformed("a part's Content-Range is not \"bytes first-last/total\"");
    }
    if (!range) malformed("a part has no Content-Range");
    return *range;
}

}  // namespace

MergedRanges merge_ranges(std::span<const ByteRange> ranges, std::uint64_t max_gap) {
    std::vector<std::size_t> order(ranges.size());
    for (std::size_t i = 0; i < order.size(); ++i) order[i] = i;
    std::sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) {
        return ranges[a].offset != ranges[b].offset ? ranges[a].offset < ranges[b].offset
                                                    : ranges[a].length > ranges[b].length;
    });
    MergedRanges out;
    out.slices.resize(ranges.size());
    std::uint64_t asked = 0, end = 0;  // asked: bytes of the ranges' union; end: one past the last span
    for (const std::size_t i : order) {
        const ByteRange& r = ranges[i];
        const bool joins = !out.spans.empty() && (r.offset <= end || r.offset - end <= max_gap);
        if (!joins) {
            out.spans.push_back({r.offset, 0});
            end = r.offset;
        }
        if (r.offset + r.length > end) {
            asked += r.offset + r.length - std::max(end, r.offset);
            end = r.offset + r.length;
        }
        out.spans.back().length = end - out.spans.back().offset;
        out.slices[i] = {out.spans.size() - 1, r.offset - out.spans.back().offset};
    }
    std::uint64_t spanned = 0;
    for (const auto& s : out.spans) spanned += s.length;
    out.waste = spanned - asked;
    return out;
}

std::vector<std::vector<std::uint8_t>> cut_parts(const MergedRanges& merged, std::span<const ByteRange> ranges,
                                                 const std::vector<std::vector<std::uint8_t>>& span_parts) {
    std::vector<std::vector<std::uint8_t>> parts(ranges.size());
    for (std::size_t i = 0; i < ranges.size(); ++i) {
        const auto& slice = merged.slices[i];
        const auto& whole = span_parts.at(slice.span);
        if (slice.skip >= whole.size()) continue;  // the file ended before the range
        const std::uint64_t n = std::min<std::uint64_t>(ranges[i].length, whole.size() - slice.skip);
        const auto first = whole.begin() + static_cast<std::ptrdiff_t>(slice.skip);
        parts[i].assign(first, first + static_cast<std::ptrdiff_t>(n));
    }
    return parts;
}

std::string range_header(std::span<const ByteRange> ranges) {
    std::string out = "bytes=";
    for (std::size_t i = 0; i < ranges.size(); ++i) {
        if (i) out += ',';
        out += std::to_string(ranges[i].offset) + '-' + std::to_string(ranges[i].last());
    }
    return out;
}

std::optional<ContentRange> parse_content_range(std::string_view value) {
    value = trim(value);
    if (!iequals_prefix(value, "bytes ")) return std::nullopt;
    value = trim(value.substr(6));
    const auto dash = value.find('-');
    const auto slash = value.find('/');
    if (dash == std::string_view::npos || slash == std::string_view::npos || slash < dash) return std::nullopt;
    const auto first = parse_number(value.substr(0, dash));
    const auto last = parse_number(value.substr(dash + 1, slash - dash - 1));
    if (!first || !last || *last < *first || *last == UINT64_MAX) return std::nullopt;
    ContentRange out{{*first, *last - *first + 1}, std::nullopt};
    const auto total = value.substr(slash + 1);
    if (total != "*") {
        out.total = parse_number(total);
        if (!out.total || *out.total <= *last) return std::nullopt;
    }
    return out;
}

std::string multipart_boundary(std::string_view content_type) {
    content_type = trim(content_type);
    if (!iequals_prefix(content_type, "multipart/byteranges")) return {};
    const auto key = content_type.find("boundary=");
    if (key == std::string_view::npos) return {};
    auto b = content_type.substr(key + 9);
    b = b.substr(0, b.find(';'));
    b = trim(b);
    if (b.size() >= 2 && b.front() == '"' && b.back() == '"') b = b.substr(1, b.size() - 2);
    if (b.empty() || b.size() > 70) return {};  // RFC 2046: 1 to 70 characters
    return std::string(b);
}

std::vector<BodyPart> parse_multipart_byteranges(std::span<const std::uint8_t> body, std::string_view boundary) {
    if (boundary.empty()) malformed("no boundary");
    const std::string delimiter = "--" + std::string(boundary);
    Cursor c(body);
    std::vector<BodyPart> parts;
    c.skip_crlf();  // a preamble of blank lines (nginx starts with one)
    for (;;) {
        c.expect(delimiter, "the boundary");
        if (c.starts_with("--")) break;  // the closing delimiter
        c.expect("\r\n", "a line end after the boundary");
        const ContentRange range = read_part_headers(c);
        parts.push_back({range, c.take(range.range.length)});
        c.expect("\r\n", "a line end after a part's data");
    }
    if (parts.empty()) malformed("no parts");
    return parts;
}

}  // namespace lidarscout::net
