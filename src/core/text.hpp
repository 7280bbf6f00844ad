// Text read from files (header strings, VLR descriptions, GeoTIFF ASCII, WKT), made fit for
// a terminal and for JSON: valid UTF-8 is kept, any other byte is taken as Latin-1, and
// control characters are escaped as \xNN, so the result is always valid UTF-8. And counts written
// for people, in the unit that fits their magnitude.
#pragma once

#include <cstddef>
#include <string>
#include <string_view>

namespace lidarscout {

std::string display_text(std::string_view bytes);

// display_text of at most the first `max_bytes` bytes of `bytes` (cut at a UTF-8 boundary), followed
// by "... (N bytes)" naming the whole length when it was cut: for text from a file or server put
// in a message (an id, an href, a type), which must never be copied whole.
inline constexpr std::size_t kExcerptBytes = 200;
std::string display_excerpt(std::string_view bytes, std::size_t max_bytes = kExcerptBytes);

// `s` with ASCII letters in lower case (other bytes unchanged), e.g. for HTTP header names.
std::string ascii_lower(std::string_view s);

// A count in the unit that fits it, to three significant digits: "950", "12.3 k", "1.01 M", "2.27 G",
// "4.10 T" (a count under 1,000 as a whole number; negative counts keep their sign).
std::string count_text(double count);

// Appends the UTF-8 encoding of `code` (a Unicode code point) to `out`.
void append_utf8(std::string& out, unsigned long code);

}  // namespace lidarscout
