// Test helpers shared by the encoder tests: encode records chunk by chunk through
// encode_chunk, decode them back through decode_chunk, and find the first differing record.
#pragma once

#include <algorithm>
#include <cstdint>
#include <span>
#include <vector>

#include "las/laszip_vlr.hpp"
#include "laz/chunk_decoder.hpp"
#include "laz/chunk_encoder.hpp"
#include "laz/laz.hpp"

namespace lidarscout::laz::codec_test {

// Chunks one after the other (byte offsets relative to the first chunk).
struct Encoded {
    std::vector<std::uint8_t> bytes;
    std::vector<Chunk> chunks;
};

inline Encoded encode_in_chunks(const las::LaszipVlr& laz, std::span<const std::uint8_t> records,
                                std::uint64_t chunk_size) {
    const std::size_t rl = laz.record_length();
    const std::uint64_t total = records.size() / rl;
    Encoded e;
    for (std::uint64_t first = 0; first < total; first += chunk_size) {
        const std::uint64_t n = std::min(chunk_size, total - first);
        const std::size_t at = e.bytes.size();
        encode_chunk(laz, records.subspan(first * rl, n * rl), n, e.bytes);
        e.chunks.push_back({first, n, at, e.bytes.size() - at});
    }
    return e;
}

inline std::vector<std::uint8_t> decode_chunks(const las::LaszipVlr& laz, const Encoded& e) {
    const std::size_t rl = laz.record_length();
    std::uint64_t total = 0;
    for (const Chunk& c : e.chunks) total += c.point_count;
    std::vector<std::uint8_t> out(total * rl);
    for (const Chunk& c : e.chunks) {
        decode_chunk(laz, {std::span(e.bytes).subspan(c.byte_offset, c.byte_size), c.point_count,
                           std::span(out).subspan(c.first_point * rl, c.point_count * rl)});
    }
    return out;
}

// Index of the first differing record, -1 if none, -2 for different sizes.
inline long first_difference(std::span<const std::uint8_t> a, std::span<const std::uint8_t> b, std::size_t rl) {
    if (a.size() != b.size()) return -2;
    const auto m = std::mismatch(a.begin(), a.end(), b.begin());
    return m.first == a.end() ? -1 : static_cast<long>((m.first - a.begin()) / static_cast<long>(rl));
}

}  // namespace lidarscout::laz::codec_test
