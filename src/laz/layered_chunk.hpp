// Decoding of one layered LAZ chunk (compressor 3: LAS 1.4 point formats 6-10, items
// POINT14, RGB14, RGBNIR14, WAVEPACKET14 and BYTE14 in versions 3 and 4). Such a chunk holds
// the first point raw, then a point count, the byte size of every layer of every item, and
// the layers themselves, each an independent arithmetic-coded stream. Layers of fields the
// caller did not ask for are skipped without being entropy-decoded.
#pragma once

#include <cstdint>

#include "laz/chunk_decoder.hpp"

namespace lidarscout::laz {

// What decoding one layered chunk read (e.g. to see that unwanted layers were skipped).
struct LayeredChunkStats {
    std::uint32_t layers = 0;          // layers in the chunk, over all items
    std::uint32_t layers_decoded = 0;  // layers that were entropy-decoded
    std::uint64_t layer_bytes = 0;     // bytes of all layers
    std::uint64_t bytes_consumed = 0;  // bytes the entropy decoders took from their layers
};

// Decodes one layered chunk (see decode_chunk for the contract); throws lidarscout::Error
// (offset within the chunk when known, no file name) for corrupt or unsupported data.
void decode_layered_chunk(const las::LaszipVlr& laz, const ChunkDecodeRequest& request);
// The same, also reporting what was read.
void decode_layered_chunk(const las::LaszipVlr& laz, const ChunkDecodeRequest& request, LayeredChunkStats& stats);

}  // namespace lidarscout::laz
