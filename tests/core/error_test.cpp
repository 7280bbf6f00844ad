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

TEST(ErrorRecord, KeepsTheFieldsAndTheMessage) {
    const Error e("a.laz", 120, "truncated");
    const auto r = ErrorRecord::of(e);
    EXPECT_EQ(r.file, "a.laz");
    EXPECT_EQ(r.offset, 120u);
    EXPECT_EQ(r.cause, "truncated");
    EXPECT_EQ(r.message(), e.what());
    EXPECT_EQ((ErrorRecord{"", std::nullopt, "network"}).message(), "network");
}

TEST(ErrorRecord, FirstErrorPerFileCountsTheRest) {
    const std::vector<ErrorRecord> errors = {{"a.laz", 1, "x"}, {"b.laz", std::nullopt, "gone"}, {"a.laz", 2, "y"},
                                             {"", std::nullopt, "net"}, {"", std::nullopt, "net"}, {"a.laz", 3, "z"}};
    const auto grouped = first_error_per_file(errors);
    ASSERT_EQ(grouped.size(), 4u);
    EXPECT_EQ(grouped[0].first.file, "a.laz");
    EXPECT_EQ(grouped[0].first.offset, 1u);
    EXPECT_EQ(grouped[0].count, 3u);
    EXPECT_EQ(grouped[1].first.file, "b.laz");
    EXPECT_EQ(grouped[1].count, 1u);
    EXPECT_EQ(grouped[2].count, 1u);  // records without a file stand alone
    EXPECT_EQ(grouped[3].count, 1u);
}

}  // namespace
}  // namespace lidarscout
