// The two loading stages every dataset command runs, behind progress bars (`scan`, `render`):
// headers and chunk tables, then the chunk points.
#pragma once

#include <string>
#include <vector>

#include "dataset/chunk_point_loader.hpp"
#include "dataset/dataset.hpp"

namespace lidarscout::cli {

// open_dataset with a "headers" progress bar.
dataset::Dataset open_with_progress(const std::vector<std::string>& paths, dataset::DatasetOptions options);

// Starts `loader` and waits until every tile is done, drawing "chunk points" progress.
void load_with_progress(dataset::ChunkPointLoader& loader);

}  // namespace lidarscout::cli
