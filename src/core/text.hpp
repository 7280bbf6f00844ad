// Text read from files (header strings, VLR descriptions, GeoTIFF ASCII, WKT), made fit for
// a terminal and for JSON: valid UTF-8 is kept, any other byte is taken as Latin-1, and
// control characters are escaped as \xNN, so the result is always valid UTF-8.
#pragma once

#include <string>
#include <string_view>

namespace lidarscout {

std::string display_text(std::string_view bytes);

// `s` with ASCII letters in lower case (other bytes unchanged), e.g. for HTTP header names.
std::string ascii_lower(std::string_view s);

}  // namespace lidarscout
