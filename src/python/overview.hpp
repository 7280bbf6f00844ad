// The overview of a dataset for Python: every chunk point of every tile (dataset/chunk_points.hpp:
// what `scan` loads), placed in the frame CRS's units as a region's points are
// (pipelines::FrameUnits), in one PointTable, tiles read in parallel.
#pragma once

#include <vector>

#include "core/error.hpp"
#include "dataset/dataset.hpp"
#include "python/point_table.hpp"

namespace lidarscout::python {

struct Overview {
    PointTable points;  // tile by tile in dataset order, each tile's in file order
    std::vector<ErrorRecord> skipped;  // tiles whose chunk points could not be read (left out)
};

// `threads` 0: every core. Never throws for one bad tile (it is named in `skipped`).
Overview read_overview(const dataset::Dataset& ds, unsigned threads);

}  // namespace lidarscout::python
