// Clipping a dataset to an area: the full-resolution points of the tiles touching it that lie in
// the area and pass a filter, written as one LAS or LAZ file with our encoder (laz::LasWriter,
// through a temporary name): the first touched tile's point format, header fields (version,
// scale/offset, system identifier, software), VLRs (hence CRS) and loaded EVLRs are kept, and the
// records of the kept points are copied byte for byte (their X/Y/Z re-quantized only for a tile
// whose scale or offset differs from the output's). Also what `profile -o OUT.laz` writes.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "pipelines/region_points.hpp"

namespace lidarscout::pipelines {

struct ClipRequest {
    std::string output;  // .las or .laz (by the extension)
    Region region;
    PointFilter filter;
    ReadWatch watch;  // progress; a cancel ends it with an Error, nothing written
};

struct ClipResult {
    RegionReadStats read;
    std::uint64_t points_written = 0, bytes_written = 0;
    std::vector<std::string> notes;  // what was not carried over (EVLRs whose payload was not loaded)
};

// Throws lidarscout::Error (stage "clip") when no tile touches the area, when the touched tiles
// have different point formats or record lengths (naming two of them), or when a touched tile is
// reprojected into the dataset's frame (its raw coordinates would need a new CRS: naming it), and
// when request.watch cancels it ("clip: cancelled"; the temporary file removed).
ClipResult clip_to_file(const dataset::Dataset& ds, const ClipRequest& request, ThreadPool& pool);

}  // namespace lidarscout::pipelines
