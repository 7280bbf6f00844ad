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
//
// Every point format and version is written as read, to LAS and to LAZ alike (wave packets of
// formats 4, 5, 9 and 10 included; a LAS 1.5 header with the kept points' GPS time range). What a
// clip cannot hold is the rule of `convert`: refused naming it, or with force dropped with a note.
// That is waveform data (in the file, or in an external .wdp file): the wave packets address it in
// their own tile, so a clip refuses a touched tile that has it, and with force writes its points'
// wave packets as "no waveform" (descriptor index, data offset and size 0, return point location and
// direction kept) and drops the waveform data EVLR. So is a CRS stated by GeoTIFF keys that point
// formats 6-10 need as WKT when PROJ cannot write it so (user-defined keys): refused, or with force the
// keys kept as they are (convert's rule, pipelines/output_records.hpp).
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
    bool force = false;  // drop what the output cannot hold (waveform data, a CRS as WKT) instead of refusing
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
// and a CRS without EPSG code), and when request.watch cancels it ("clip: cancelled"); naming the
// tile, when a touched tile has waveform data, or the first one's CRS cannot be written as its point
// format needs, and request.force is not set.
ClipResult clip_to_file(const dataset::Dataset& ds, const ClipRequest& request, ThreadPool& pool);

}  // namespace lidarscout::pipelines
