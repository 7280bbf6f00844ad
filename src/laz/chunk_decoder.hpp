// (internal to laz) Decoding one LAZ chunk into raw LAS point records (the bytes a LAS file would hold),
// for every compressor: point-wise (1, 2) and layered (3). Chunks are independent, so
// callers decode them in parallel. A subset of fields can be asked for: for layered
// chunks the other layers are then not entropy-decoded at all.
#pragma once

#include <cstdint>
#include <span>

#include "las/laszip_vlr.hpp"
#include "laz/laz.hpp"  // fields

namespace lidarscout::laz {

struct ChunkDecodeRequest {
    std::span<const std::uint8_t> bytes;  // the chunk's compressed bytes (byte_offset .. +byte_size)
    std::uint64_t point_count = 0;        // points in this chunk
    std::span<std::uint8_t> out;          // point_count * record_length bytes
    std::uint32_t fields = fields::kAll;
};

// Decodes one chunk; throws lidarscout::Error (cause, offset within the chunk when known;
// no file name: the caller adds file and chunk index) for corrupt or unsupported data.
void decode_chunk(const las::LaszipVlr& laz, const ChunkDecodeRequest& request);

}  // namespace lidarscout::laz
