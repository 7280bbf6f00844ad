// The ASPRS standard point classes of LAS 1.4 (R15, table 17): their names, for readouts.
#pragma once

#include <cstdint>
#include <string>

namespace lidarscout::las {

// "ground", "high vegetation", ... for the standard classes 0-18; "reserved (n)" for 19-63 and
// "user defined (n)" for 64-255.
std::string class_name(std::uint8_t classification);

}  // namespace lidarscout::las
