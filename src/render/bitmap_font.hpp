// Text in an RGBA image without a font library: a 5 x 7 pixel font of our own (digits, ASCII letters and
// the punctuation of axis labels), each font pixel drawn as a square of `scale` image pixels. For the
// labels of images the program writes (the profile PNG's axes); a character the font lacks is drawn
// as a hollow box, so a missing glyph shows instead of vanishing.
#pragma once

#include <cstdint>
#include <string_view>

#include "render/resolve.hpp"

namespace lidarscout::render {

inline constexpr int kGlyphWidth = 5, kGlyphHeight = 7;
inline constexpr int kGlyphAdvance = kGlyphWidth + 1;  // a column of space between characters

// The 7 rows of `c`, top first, 5 bits each (bit 4 the leftmost column); nullptr when the font lacks it.
const std::uint8_t* glyph_rows(char c);

// Width and height in image pixels of `text` on one line at `scale`.
int text_width(std::string_view text, int scale);
inline int text_height(int scale) { return kGlyphHeight * scale; }

// Draws `text` with its top left corner at (x, y); pixels outside the image are skipped.
void draw_text(RgbaImage& image, int x, int y, std::string_view text, std::uint32_t colour, int scale = 1);

// The same turned a quarter left (reading bottom to top), its bottom left corner at (x, y): a
// vertical axis's title.
void draw_text_up(RgbaImage& image, int x, int y, std::string_view text, std::uint32_t colour, int scale = 1);

}  // namespace lidarscout::render
