// Text read from files (header strings, VLR descriptions, GeoTIFF ASCII, WKT), made fit for
// a terminal and for JSON: valid UTF-8 is kept, any other byte is taken as Latin-1, and
// control characters are escaped as \xNN, so the result is always valid UTF-8.
#pragma once

#include <string>
#include <string_view>

namespace lidarscout {

std::string display_text(std::string_view bytes);

}  // namespace lidarscout
