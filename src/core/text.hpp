// Text read from files (header strings, VLR descriptions, GeoTIFF ASCII, WKT), made fit for
// a terminal and for JSON: valid UTF-8 is kept, any other byte is taken as Latin-1, and
// control characters are escaped as \xNN, so the result is always valid UTF-8.
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

}  // namespace lidarscout
