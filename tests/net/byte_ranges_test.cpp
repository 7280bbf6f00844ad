// net/byte_ranges: Range headers, Content-Range values and multipart/byteranges bodies (as
// nginx sends them), and malformed bodies rejected with an error, never read out of bounds; ranges
// merged into spans by their gaps and cut back out of the spans' bytes.
#include <gtest/gtest.h>

#include "core/error.hpp"
#include "net/byte_ranges.hpp"

namespace lidarscout::net {
namespace {

std::span<const std::uint8_t> bytes(const std::string& s) {
    return {reinterpret_cast<const std::uint8_t*>(s.data()), s.size()};
}

std::string as_text(std::span<const std::uint8_t> b) { return {b.begin(), b.end()}; }

TEST(ByteRanges, RangeHeaderListsInclusiveRanges) {
    const std::vector<ByteRange> r = {{0, 10}, {100, 1}, {4096, 4096}};
    EXPECT_EQ(range_header(r), "bytes=0-9,100-100,4096-8191");
}

// Ranges at most the gap apart become one span (in any order asked, overlapping or not); the waste is
// the spans' bytes outside every range; each range is cut back out of its span's bytes.
TEST(ByteRanges, NearRangesMergeIntoSpansAndAreCutBackOut) {
    const std::vector<ByteRange> r = {{1000, 10}, {0, 4}, {20, 4}, {1012, 8}, {22, 4}, {5000, 1}};
    const auto merged = merge_ranges(r, 16);
    const std::vector<ByteRange> spans = {{0, 26}, {1000, 20}, {5000, 1}};
    EXPECT_EQ(merged.spans, spans);
    EXPECT_EQ(merged.waste, 16u + 2u);  // 4..19, and 1010..1011 (20..25 asked twice counts once)
    ASSERT_EQ(merged.slices.size(), r.size());
    EXPECT_EQ(merged.slices[0].span, 1u);
    EXPECT_EQ(merged.slices[3].skip, 12u);
    EXPECT_EQ(merged.slices[4].skip, 22u);

    std::string file(6000, '\0');
    for (std::size_t i = 0; i < file.size(); ++i) file[i] = static_cast<char>('a' + i % 23);
    std::vector<std::vector<std::uint8_t>> span_parts;
    for (const auto& s : spans) span_parts.emplace_back(file.begin() + s.offset, file.begin() + s.offset + s.length);
    const auto parts = cut_parts(merged, r, span_parts);
    ASSERT_EQ(parts.size(), r.size());
    for (std::size_t i = 0; i < r.size(); ++i) EXPECT_EQ(as_text(parts[i]), file.substr(r[i].offset, r[i].length)) << i;

    EXPECT_EQ(merge_ranges(r, 0).spans.size(), 5u);  // only the overlapping 20..23 and 22..25 join
    EXPECT_EQ(merge_ranges(r, 4000).spans.size(), 1u);
    EXPECT_EQ(merge_ranges(r, UINT64_MAX).spans.size(), 1u);  // (no overflow)
    EXPECT_TRUE(merge_ranges({}, 16).spans.empty());
}

// A span cut short by the end of the file: its ranges are cut short too (the caller sees a short read).
TEST(ByteRanges, ASpanEndingEarlyCutsItsRangesShort) {
    const std::vector<ByteRange> r = {{0, 4}, {8, 4}, {14, 4}};
    const auto merged = merge_ranges(r, 8);
    ASSERT_EQ(merged.spans.size(), 1u);
    const std::vector<std::vector<std::uint8_t>> span_parts = {std::vector<std::uint8_t>(10, 7)};
    const auto parts = cut_parts(merged, r, span_parts);
    EXPECT_EQ(parts[0].size(), 4u);
    EXPECT_EQ(parts[1].size(), 2u);
    EXPECT_TRUE(parts[2].empty());
}

TEST(ByteRanges, ContentRangeIsParsedStrictly) {
    const auto a = parse_content_range("bytes 10-19/100");
    ASSERT_TRUE(a);
    EXPECT_EQ(a->range, (ByteRange{10, 10}));
    EXPECT_EQ(a->total, 100u);
    const auto b = parse_content_range("bytes 0-0/*");
    ASSERT_TRUE(b);
    EXPECT_FALSE(b->total);
    for (const char* bad : {"bytes 10-9/100", "bytes 0-99/99", "items 0-1/2", "bytes -5/10", "bytes 1-2", "bytes a-b/c",
                            "bytes 0-18446744073709551615/*", "bytes */100"}) {
        EXPECT_FALSE(parse_content_range(bad)) << bad;
    }
}

TEST(ByteRanges, BoundaryComesFromTheMultipartContentType) {
    EXPECT_EQ(multipart_boundary("multipart/byteranges; boundary=00000000000000000001"), "00000000000000000001");
    EXPECT_EQ(multipart_boundary("multipart/byteranges; boundary=\"a b\""), "a b");
    EXPECT_EQ(multipart_boundary("application/octet-stream"), "");
    EXPECT_EQ(multipart_boundary("multipart/byteranges"), "");
}

const std::string kNginxBody =
    "\r\n--00000000000000000001\r\nContent-Type: application/octet-stream\r\nContent-Range: bytes 0-3/20\r\n\r\n"
    "LASF\r\n--00000000000000000001\r\nContent-Type: application/octet-stream\r\nContent-Range: bytes 10-14/20\r\n\r\n"
    "ab\r\n-\r\n--00000000000000000001--\r\n";

TEST(ByteRanges, MultipartBodyIsSplitByContentRangeLengths) {
    const auto parts = parse_multipart_byteranges(bytes(kNginxBody), "00000000000000000001");
    ASSERT_EQ(parts.size(), 2u);
    EXPECT_EQ(parts[0].content_range.range, (ByteRange{0, 4}));
    EXPECT_EQ(as_text(parts[0].data), "LASF");
    EXPECT_EQ(parts[1].content_range.range, (ByteRange{10, 5}));
    EXPECT_EQ(as_text(parts[1].data), "ab\r\n-");  // data may hold CRLF and dashes
}

TEST(ByteRanges, MalformedMultipartBodiesAreErrors) {
    const std::string boundary = "00000000000000000001";
    EXPECT_THROW(parse_multipart_byteranges(bytes("no boundary here"), boundary), Error);
    EXPECT_THROW(parse_multipart_byteranges(bytes("--" + boundary + "--\r\n"), boundary), Error);  // no parts
    // every prefix of a good body is an error (cut bodies), never an out-of-bounds read
    for (std::size_t n = 0; n + 4 < kNginxBody.size(); ++n) {
        EXPECT_THROW(parse_multipart_byteranges(bytes(kNginxBody.substr(0, n)), boundary), Error) << n;
    }
    std::string lying = kNginxBody;
    lying.replace(lying.find("10-14"), 5, "10-99");  // a part longer than the body
    EXPECT_THROW(parse_multipart_byteranges(bytes(lying), boundary), Error);
    std::string no_range = kNginxBody;
    no_range.replace(no_range.find("Content-Range"), 7, "X-Other");
    EXPECT_THROW(parse_multipart_byteranges(bytes(no_range), boundary), Error);
}

}  // namespace
}  // namespace lidarscout::net
