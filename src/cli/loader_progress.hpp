// Running the chunk-point loader to the end behind a progress bar (`scan`, `render`).
#pragma once

#include "dataset/chunk_point_loader.hpp"

namespace lidarscout::cli {

// Starts `loader` and waits until every tile is done, drawing "chunk points" progress.
void load_with_progress(dataset::ChunkPointLoader& loader);

}  // namespace lidarscout::cli
