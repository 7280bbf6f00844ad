// The byte-range parts of HTTP: the Range header a client sends, the Content-Range header a
// server answers with, and a multipart/byteranges body (RFC 9110 §14) split into its parts.
// Pure functions on bytes; malformed input gives a lidarscout::Error (without a file; the
// caller names the URL), never a read out of bounds.
#pragma once

#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

namespace lidarscout::net {

struct ByteRange {
    std::uint64_t offset = 0;
    std::uint64_t length = 0;  // > 0
    std::uint64_t last() const { return offset + length - 1; }
    bool operator==(const ByteRange&) const = default;
};

// Ranges gathered into fewer requests: the ranges asked (in any order, overlapping or not) as
// sorted spans, each covering ranges whose gaps are at most the gap allowed, and where each range
// asked lies in its span. A server that answers one range per request (S3) then costs a request
// per span, not per range: the bytes between merged ranges are read and dropped.
struct MergedRanges {
    struct Slice {
        std::size_t span = 0;    // index into spans
        std::uint64_t skip = 0;  // the range's first byte, from its span's first
    };
    std::vector<ByteRange> spans;  // sorted, disjoint, more than max_gap bytes apart
    std::vector<Slice> slices;     // one per range asked, in the order asked
    std::uint64_t waste = 0;       // bytes of the spans outside every range asked
};

MergedRanges merge_ranges(std::span<const ByteRange> ranges, std::uint64_t max_gap);

// The parts of the ranges asked, cut from the parts that answered the spans (one per span; a span's
// part may end early at the end of the file, and the ranges cut from it then do too).
std::vector<std::vector<std::uint8_t>> cut_parts(const MergedRanges& merged, std::span<const ByteRange> ranges,
                                                 const std::vector<std::vector<std::uint8_t>>& span_parts);

// "bytes=a-b,c-d,..." for the ranges in the order given.
std::string range_header(std::span<const ByteRange> ranges);

struct ContentRange {
    ByteRange range;
    std::optional<std::uint64_t> total;  // absent for "/*"
};

// "bytes first-last/total" (or "/*"); nothing when the value is not of that form.
std::optional<ContentRange> parse_content_range(std::string_view value);

// The boundary of a "multipart/byteranges; boundary=..." Content-Type; empty for any other type.
std::string multipart_boundary(std::string_view content_type);

struct BodyPart {
    ContentRange content_range;
    std::span<const std::uint8_t> data;  // points into the body given to the parser
};

// The parts of a multipart/byteranges body, in the order sent. Each part's length is taken
// from its Content-Range (not by searching for the boundary in the data). Throws Error when
// the body does not follow the format.
std::vector<BodyPart> parse_multipart_byteranges(std::span<const std::uint8_t> body, std::string_view boundary);

}  // namespace lidarscout::net
