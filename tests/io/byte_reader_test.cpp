// io::ByteReader: little-endian fields in order, NUL-trimmed fixed strings, and every read past
// the end an Error naming the file and the absolute offset where the field starts.
#include "io/byte_reader.hpp"

#include <gtest/gtest.h>

#include <cstdint>
#include <string>
#include <vector>

namespace lidarscout::io {
namespace {

TEST(ByteReader, ReadsLittleEndianFieldsInOrder) {
    const std::vector<std::uint8_t> bytes = {0x01, 0x34, 0x12, 0x78, 0x56, 0x34, 0x12, 'a', 'b', 0, 'z', 0xFF};
    ByteReader r(bytes, 1000, "t.las");
    EXPECT_EQ(r.u8(), 0x01);
    EXPECT_EQ(r.u16(), 0x1234);
    EXPECT_EQ(r.u32(), 0x12345678u);
    EXPECT_EQ(r.file_offset(), 1007u);
    EXPECT_EQ(r.fixed_string(4), "ab");  // stops at the NUL, consumes all four bytes
    EXPECT_EQ(r.i8(), -1);
    EXPECT_EQ(r.remaining(), 0u);
    r.seek(1);
    EXPECT_EQ(r.i16(), 0x1234);
    EXPECT_EQ(load_le<std::uint16_t>(bytes.data() + 1), 0x1234);
}

TEST(ByteReader, ReadingPastTheEndNamesFileAndOffset) {
    const std::vector<std::uint8_t> bytes = {1, 2, 3};
    ByteReader r(bytes, 500, "t.las");
    r.skip(2);
    try {
        r.u32("point count");
        FAIL() << "no error";
    } catch (const Error& e) {
        EXPECT_EQ(e.file(), "t.las");
        EXPECT_EQ(e.offset(), 502u);
        EXPECT_NE(e.cause().find("truncated point count: needs 4 bytes, only 1 left"), std::string::npos) << e.cause();
    }
    EXPECT_THROW(r.seek(4), Error);
    EXPECT_EQ(r.position(), 2u);  // a failed read or seek moves nothing
}

}  // namespace
}  // namespace lidarscout::io
