// decode_chunk: dispatch on the compressor (point-wise 1/2 or layered 3).
#include "laz/chunk_decoder.hpp"

#include "core/error.hpp"
#include "laz/layered_chunk.hpp"
#include "laz/pointwise_chunk.hpp"

namespace lidarscout::laz {

void decode_chunk(const las::LaszipVlr& laz, const ChunkDecodeRequest& request) {
    switch (laz.compressor) {
        case 1:
        case 2: decode_pointwise_chunk(laz, request); return;
        case 3: decode_layered_chunk(laz, request); return;
        default: throw Error("unsupported LAZ compressor " + std::to_string(laz.compressor));
    }
}

}  // namespace lidarscout::laz
