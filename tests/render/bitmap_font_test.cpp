// The bitmap font: a glyph for every character the profile's labels use, each distinct from the
// others; text drawn where asked (and turned up for a vertical title), clipped at the image's edges;
// a character the font lacks drawn as a box.
#include <gtest/gtest.h>

#include <set>
#include <string>
#include <vector>

#include "render/bitmap_font.hpp"
#include "render/framebuffer.hpp"

namespace lidarscout::render {
namespace {

const std::uint32_t kInk = pack_rgba(255, 255, 255), kPaper = pack_rgba(0, 0, 0);

RgbaImage paper(int width, int height) {
    return {width, height, std::vector<std::uint32_t>(static_cast<std::size_t>(width) * height, kPaper)};
}

std::vector<std::pair<int, int>> inked(const RgbaImage& image) {
    std::vector<std::pair<int, int>> out;
    for (int y = 0; y < image.height; ++y) {
        for (int x = 0; x < image.width; ++x) {
            if (image.at(x, y) == kInk) out.emplace_back(x, y);
        }
    }
    return out;
}

TEST(BitmapFont, EveryLabelCharacterHasItsOwnGlyph) {
    const std::string chars = "0123456789.,-+()/:%='_ abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVWXYZ";
    std::set<std::vector<std::uint8_t>> seen;
    for (const char c : chars) {
        const std::uint8_t* rows = glyph_rows(c);
        ASSERT_NE(rows, nullptr) << c;
        for (int r = 0; r < kGlyphHeight; ++r) EXPECT_LT(rows[r], 1 << kGlyphWidth) << c;
        EXPECT_TRUE(seen.emplace(rows, rows + kGlyphHeight).second) << "the same glyph twice: " << c;
    }
    EXPECT_EQ(glyph_rows('\x01'), nullptr);
    EXPECT_EQ(glyph_rows('\xE9'), nullptr);
}

TEST(BitmapFont, DrawsWhereAskedAtItsScale) {
    EXPECT_EQ(text_width("", 2), 0);
    EXPECT_EQ(text_width("10", 1), 11);  // two glyphs and the column between them
    EXPECT_EQ(text_width("10", 3), 33);
    EXPECT_EQ(text_height(2), 14);
    auto image = paper(40, 20);
    draw_text(image, 3, 4, "1", kInk, 2);
    const auto one = inked(image);
    ASSERT_FALSE(one.empty());
    for (const auto& [x, y] : one) {
        EXPECT_GE(x, 3);
        EXPECT_LT(x, 3 + 10);
        EXPECT_GE(y, 4);
        EXPECT_LT(y, 4 + 14);
    }
    // every font pixel of '1' a 2 x 2 square
    int set = 0;
    for (int r = 0; r < kGlyphHeight; ++r) set += __builtin_popcount(glyph_rows('1')[r]);
    EXPECT_EQ(one.size(), static_cast<std::size_t>(set) * 4);
}

TEST(BitmapFont, TurnedTextReadsUpwards) {
    auto flat = paper(20, 20), up = paper(20, 20);
    draw_text(flat, 0, 0, "L", kInk);
    draw_text_up(up, 0, 19, "L", kInk);
    const auto a = inked(flat), b = inked(up);
    ASSERT_EQ(a.size(), b.size());
    for (const auto& [x, y] : a) {  // (column x, row y) of the glyph lands at (row y, up x from the baseline)
        EXPECT_EQ(up.at(y, 19 - x), kInk) << x << "," << y;
    }
}

TEST(BitmapFont, ClipsAtTheEdgesAndBoxesWhatItLacks) {
    auto image = paper(8, 8);
    draw_text(image, -3, -3, "888", kInk, 2);  // mostly outside: no write out of bounds
    draw_text(image, 6, 6, "8", kInk, 2);
    EXPECT_FALSE(inked(image).empty());
    auto box = paper(10, 10);
    draw_text(box, 0, 0, "\x01", kInk);
    EXPECT_EQ(inked(box).size(), 5u + 5u + 5u * 2);  // the outline of the 5 x 7 cell
}

}  // namespace
}  // namespace lidarscout::render
