// encode_chunk: dispatch on the compressor.
#include "laz/chunk_encoder.hpp"

#include <string>

#include "core/error.hpp"
#include "laz/layered_chunk_encoder.hpp"
#include "laz/pointwise_chunk_encoder.hpp"

namespace lidarscout::laz {

void encode_chunk(const las::LaszipVlr& laz, std::span<const std::uint8_t> records, std::uint64_t point_count,
                  std::vector<std::uint8_t>& out) {
    switch (laz.compressor) {
        case 2: encode_pointwise_chunk(laz, records, point_count, out); return;
        case 3: encode_layered_chunk(laz, records, point_count, out); return;
        default:
            throw Error("LAZ encoder: compressor " + std::to_string(laz.compressor) +
                        " cannot be written (2 point-wise chunked, 3 layered chunked)");
    }
}

}  // namespace lidarscout::laz
