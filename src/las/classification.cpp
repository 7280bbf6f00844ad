// ASPRS class names (LAS 1.4 R15, table 17).
#include "las/classification.hpp"

#include <array>

namespace lidarscout::las {

std::string class_name(std::uint8_t classification) {
    static constexpr std::array<const char*, 23> kNames = {
        "created, never classified", "unclassified", "ground", "low vegetation", "medium vegetation",
        "high vegetation", "building", "low point (noise)", "reserved (model key-point)", "water", "rail",
        "road surface", "reserved (overlap)", "wire guard (shield)", "wire conductor (phase)", "transmission tower",
        "wire-structure connector", "bridge deck", "high noise", "overhead structure", "ignored ground", "snow",
        "temporal exclusion"};
    if (classification < kNames.size()) return kNames[classification];
    const std::string n = std::to_string(classification);
    return classification < 64 ? "reserved (" + n + ")" : "user defined (" + n + ")";
}

}  // namespace lidarscout::las
