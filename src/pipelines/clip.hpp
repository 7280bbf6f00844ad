// Clipping a dataset to an area: the full-resolution points of the tiles touching it that lie in
// the area and pass a filter, written as one LAS or LAZ file with our encoder (laz::LasWriter,
// through a temporary name): the first touched tile's point format, header fields (version,
// scale/offset, system identifier, software), VLRs (hence CRS) and loaded EVLRs are kept, and the
// records of the kept points are copied byte for byte (their X/Y/Z re-quantized only for a tile
// whose scale or offset differs from the output's). When a touched tile is in another CRS than the
// dataset's frame (reprojected into it, as dem does), the output is written in the frame's CRS
// instead: its CRS records replaced by the frame's (WKT for point formats 6-10, else GeoTIFF keys of
// its EPSG code), its scale/offset those of a touched tile in that CRS (else chosen), and every
// record's X/Y/Z re-quantized from where the point lies in the frame. Also what `profile -o OUT.laz`
// writes.
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
// have different point formats or record lengths (naming two of them), when the output must be in
// the frame's CRS and cannot name it (a LAS 1.0-1.3 output of formats 0-5 and a CRS without EPSG
// code), and when request.watch cancels it ("clip: cancelled"; the temporary file removed).
ClipResult clip_to_file(const dataset::Dataset& ds, const ClipRequest& request, ThreadPool& pool);

}  // namespace lidarscout::pipelines
