// Bounded JSON documents from files or URLs.
#include "dataset/json_file.hpp"

#include <string>

#include "core/error.hpp"

namespace lidarscout::dataset {

nlohmann::json read_json_object(const io::File& file, std::uint64_t max_bytes) {
    if (file.size() > max_bytes) {
        throw Error(file.path(), std::nullopt,
                    "JSON file too large (" + std::to_string(file.size()) + " bytes, at most " +
                        std::to_string(max_bytes) + ")");
    }
    const auto bytes = file.read_vector(0, static_cast<std::size_t>(file.size()), "JSON document");
    auto json = nlohmann::json::parse(bytes.begin(), bytes.end(), nullptr, false);
    if (json.is_discarded() || !json.is_object()) throw Error(file.path(), std::nullopt, "not a JSON object");
    return json;
}

}  // namespace lidarscout::dataset
