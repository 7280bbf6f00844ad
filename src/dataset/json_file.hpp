// A JSON document read from a file or URL (through io::File), bounded in size: what the dataset
// stage's JSON inputs (EPT metadata and hierarchies, STAC catalogs) share. Internal to the
// dataset stage (nlohmann_json is its private dependency).
#pragma once

#include <cstdint>
#include <string>

#include <nlohmann/json.hpp>

#include "io/file.hpp"

namespace lidarscout::dataset {

// The document, which must be a JSON object of at most `max_bytes`. Throws lidarscout::Error
// naming the file otherwise (too large, not JSON, not an object).
nlohmann::json read_json_object(const io::File& file, std::uint64_t max_bytes);

}  // namespace lidarscout::dataset
