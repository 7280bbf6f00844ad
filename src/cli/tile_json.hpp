// JSON form of a tile's metadata and chunk points (the `info --json` schema, see README).
#pragma once

#include <nlohmann/json.hpp>

#include <optional>
#include <string>
#include <vector>

#include "core/error.hpp"
#include "dataset/chunk_points.hpp"
#include "dataset/tile.hpp"
#include "geo/projection.hpp"

namespace lidarscout::cli {

nlohmann::json tile_to_json(const dataset::Tile& tile);
nlohmann::json chunks_to_json(const dataset::Tile& tile);
nlohmann::json chunk_points_to_json(const std::vector<dataset::ChunkPoint>& points, const dataset::Tile& tile);

// The object of a file that could not be read: every field null but `path` and `error`.
nlohmann::json failed_tile_json(const std::string& path, const std::string& error);
// Errors kept while working on: [{"file": ..., "offset": n or null, "cause": ...}, ...].
nlohmann::json error_list_json(const std::vector<ErrorRecord>& errors);

}  // namespace lidarscout::cli
