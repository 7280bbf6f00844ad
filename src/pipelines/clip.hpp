// Clipping a dataset to an area: the full-resolution points of the tiles touching it that lie in
// the area and pass a filter, written as one LAS or LAZ file with our encoder (laz::LasWriter,
// through a temporary name): the first touched tile's point format, header fields (version,
// scale/offset, system identifier, software), VLRs and loaded EVLRs are kept (not its COPC records),
// and the records of the kept points are copied byte for byte (their X/Y/Z re-quantized only for a
// tile whose scale or offset differs from the output's). The output states one CRS, once, in the
// form its point format expects (pipelines/output_records.hpp): the first tile's, or, when a touched
// tile is in another CRS than the dataset's frame (reprojected into it, as dem does), the frame's:
// its scale/offset then those of a touched tile in that CRS (else chosen), and every record's X/Y/Z
// re-quantized from where the point lies in the frame. A frame in degrees (DatasetOptions::
// accept_degrees) is clipped in degrees. Also what `profile -o OUT.laz` writes.
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
    std::string command = "clip";      // who asks, naming its empty result
    std::string where = "the region";  // the region as that command names it ("the corridor")
};

struct ClipResult {
    RegionReadStats read;
    std::uint64_t points_written = 0, bytes_written = 0;
    std::vector<std::string> notes;  // what was not carried over (EVLRs whose payload was not loaded)
};

// Throws lidarscout::Error, nothing written (the temporary file removed): of request.command when no
// tile touches the area or no point is kept (require_touched_tiles, require_kept_points); of stage
// "clip" when the touched tiles have different point formats or record lengths (naming two of them),
// when the output must be in the frame's CRS and cannot name it (a LAS 1.0-1.3 output of formats 0-5
// and a CRS without EPSG code), and when request.watch cancels it ("clip: cancelled").
ClipResult clip_to_file(const dataset::Dataset& ds, const ClipRequest& request, ThreadPool& pool);

}  // namespace lidarscout::pipelines
