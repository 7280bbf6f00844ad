// Bounded JSON documents from files or URLs.
#include "dataset/json_file.hpp"

#include <algorithm>
#include <string>

#include "core/error.hpp"

namespace lidarscout::dataset {

JsonSource file_json_source(const io::File& file) {
    return [&file, offset = std::uint64_t{0}](std::span<char> out) mutable -> std::size_t {
        // Never past the end: a remote file would spend a request to learn that nothing is there.
        if (offset >= file.size()) return 0;
        const auto want = static_cast<std::size_t>(std::min<std::uint64_t>(out.size(), file.size() - offset));
        const std::size_t n = file.read_at(offset, {reinterpret_cast<std::uint8_t*>(out.data()), want});
        offset += n;
        return n;
    };
}

nlohmann::json read_json_file(const io::File& file, const JsonLimits& limits, const JsonStreaming* streaming) {
    const std::string name = io::display_path(file.path());
    if (file.size() > limits.max_bytes) {
        throw Error(name, std::nullopt,
                    "JSON file too large (" + std::to_string(file.size()) + " bytes, at most " +
                        std::to_string(limits.max_bytes) + ")");
    }
    return read_json(file_json_source(file), name, limits, streaming);
}

nlohmann::json read_json_object(const io::File& file, const JsonLimits& limits, const JsonStreaming* streaming) {
    auto json = read_json_file(file, limits, streaming);
    if (!json.is_object()) throw Error(io::display_path(file.path()), std::nullopt, "not a JSON object");
    return json;
}

nlohmann::json read_json_object(const io::File& file, std::uint64_t max_bytes) {
    JsonLimits limits;
    limits.max_bytes = max_bytes;
    limits.kept = {max_bytes, max_bytes};
    return read_json_object(file, limits);
}

}  // namespace lidarscout::dataset
