// lidarscout::Error: the message names the file, the byte offset and the cause; a stage
// prefixes errors without a file; with_file attributes an error a lower layer raised.
#include <gtest/gtest.h>

#include "core/error.hpp"

namespace lidarscout {
namespace {

TEST(Error, MessageNamesFileOffsetAndCause) {
    const Error e("tile.laz", 375, "chunk table: bad version");
    EXPECT_STREQ(e.what(), "tile.laz: at byte 375: chunk table: bad version");
    EXPECT_EQ(e.file(), "tile.laz");
    EXPECT_EQ(e.offset(), 375u);
    EXPECT_EQ(e.cause(), "chunk table: bad version");
}

TEST(Error, WithoutOffsetOrFile) {
    EXPECT_STREQ(Error("tile.las", std::nullopt, "truncated header").what(), "tile.las: truncated header");
    const Error e("bad --memory value");
    EXPECT_STREQ(e.what(), "bad --memory value");
    EXPECT_TRUE(e.file().empty());
    EXPECT_FALSE(e.offset().has_value());
}

TEST(Error, InStagePrefixesTheStage) {
    const Error e = Error::in_stage("recon", "unknown method 'x'");
    EXPECT_STREQ(e.what(), "recon: unknown method 'x'");
    EXPECT_TRUE(e.file().empty());
}

TEST(Error, WithFileKeepsOffsetAndCause) {
    const Error e = Error(std::string(), 12, "bad byte").with_file("a.laz");
    EXPECT_STREQ(e.what(), "a.laz: at byte 12: bad byte");
    EXPECT_EQ(e.offset(), 12u);
}

}  // namespace
}  // namespace lidarscout
