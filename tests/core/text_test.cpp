// display_text: valid UTF-8 kept, other bytes as Latin-1, control characters escaped; count_text's units.
#include <gtest/gtest.h>

#include <cmath>

#include <nlohmann/json.hpp>

#include "core/text.hpp"

namespace lidarscout {
namespace {

TEST(DisplayText, KeepsAsciiAndValidUtf8) {
    EXPECT_EQ(display_text("LASF_Projection"), "LASF_Projection");
    EXPECT_EQ(display_text("Gau\xC3\x9F-Kr\xC3\xBCger \xE2\x82\xAC \xF0\x9F\x8C\x8D"),
              "Gau\xC3\x9F-Kr\xC3\xBCger \xE2\x82\xAC \xF0\x9F\x8C\x8D");
}

TEST(DisplayText, TakesOtherBytesAsLatin1) {
    EXPECT_EQ(display_text("Gau\xDF-Kr\xFCger"), "Gau\xC3\x9F-Kr\xC3\xBCger");  // ß, ü in Latin-1
    EXPECT_EQ(display_text("\xC3"), "\xC3\x83");                                // a lone lead byte
    EXPECT_EQ(display_text("\xE2\x82"), "\xC3\xA2\\x82");                     // a cut sequence
    EXPECT_EQ(display_text("\xC0\xAF"), "\xC3\x80\xC2\xAF");                    // overlong '/': two Latin-1 letters
    EXPECT_EQ(display_text("\xED\xA0\x80"), "\xC3\xAD\xC2\xA0\\x80");           // a surrogate is not UTF-8
}

TEST(DisplayText, EscapesControlCharacters) {
    EXPECT_EQ(display_text(std::string("a\0b", 3)), "a\\x00b");
    EXPECT_EQ(display_text("line\nnext\x7F"), "line\\x0Anext\\x7F");
    EXPECT_EQ(display_text("\xC2\x85"), "\\x85");  // C1 control written as UTF-8
    EXPECT_EQ(display_text("\x9B"), "\\x9B");      // C1 control as a Latin-1 byte
}

TEST(DisplayText, AnyBytesGiveValidJson) {
    std::string all;
    for (int i = 0; i < 256; ++i) all += static_cast<char>(i);
    for (int i = 255; i >= 0; --i) all += static_cast<char>(i);
    const nlohmann::json j = display_text(all);
    EXPECT_NO_THROW((void)j.dump());
    EXPECT_EQ(nlohmann::json::parse(j.dump()).get<std::string>(), display_text(all));
}

// The viewer's "0.00 G points" for a million points: the unit now follows the magnitude.
TEST(CountText, ChoosesTheUnitByMagnitude) {
    EXPECT_EQ(count_text(0), "0");
    EXPECT_EQ(count_text(950), "950");
    EXPECT_EQ(count_text(999.4), "999");
    EXPECT_EQ(count_text(999.6), "1.00 k");  // rounds up into the next unit, not "1000"
    EXPECT_EQ(count_text(12345), "12.3 k");
    EXPECT_EQ(count_text(144050), "144 k");
    EXPECT_EQ(count_text(999600), "1.00 M");  // not "1000 k"
    EXPECT_EQ(count_text(1012412), "1.01 M");
    EXPECT_EQ(count_text(2.27e6), "2.27 M");
    EXPECT_EQ(count_text(15.7e6), "15.7 M");
    EXPECT_EQ(count_text(3.1e9), "3.10 G");
    EXPECT_EQ(count_text(4.1e15), "4100 T");  // the largest unit holds what is above it
    EXPECT_EQ(count_text(-2500), "-2.50 k");
    EXPECT_EQ(count_text(std::nan("")), "?");
}

}  // namespace
}  // namespace lidarscout
