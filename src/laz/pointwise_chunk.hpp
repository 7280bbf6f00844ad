// Decoding of point-wise compressed LAZ data (compressor 1, point-wise, and compressor 2,
// point-wise chunked) with the point10-family items: POINT10, GPSTIME11, RGB12, BYTE
// (versions 1 and 2) and WAVEPACKET13 (version 1).
//
// A chunk is the first point's raw record followed by one arithmetic-coded stream that
// holds all other points, every item coded in record order. A compressor-1 file is one
// such "chunk": its point data begins directly with the raw first record (there is no
// chunk-table pointer) and runs to the end of the point data.
#pragma once

#include "laz/chunk_decoder.hpp"
#include "las/laszip_vlr.hpp"

namespace lidarscout::laz {

// Decodes `request.point_count` records into `request.out`. Point-wise streams interleave
// all fields, so every field is decoded; fields not asked for in `request.fields` are then
// zeroed, as decode_chunk promises. Throws lidarscout::Error (no file name) for an
// unsupported item list, a wrong output size, or a truncated or corrupt chunk.
void decode_pointwise_chunk(const las::LaszipVlr& laz, const ChunkDecodeRequest& request);

}  // namespace lidarscout::laz
