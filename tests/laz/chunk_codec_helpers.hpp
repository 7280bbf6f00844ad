// Test helpers shared by the encoder tests: encode records chunk by chunk through
// encode_chunk, decode them back through decode_chunk, find the first differing record, and
// make wave packets that take every path of the wave packet coder.
#pragma once

#include <algorithm>
#include <array>
#include <cstdint>
#include <cstring>
#include <random>
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

// Wave packet items (29 bytes each) whose data offsets take every path of the coder: the same
// as the last, right after it, a delta that fits 32 bits (either sign), a far jump coded raw,
// and sizes of 2 GiB and more (where "right after" is the unsigned sum); descriptor indices,
// sizes, return point locations and directions that mostly repeat.
inline std::vector<std::uint8_t> wave_packets(std::size_t n, std::uint32_t seed) {
    constexpr std::size_t kSize = 29;
    std::mt19937 rng(seed);
    const auto sometimes = [&](unsigned one_in) { return rng() % one_in == 0; };
    std::vector<std::uint8_t> out(n * kSize);
    std::uint8_t descriptor = 1;
    std::uint64_t offset = 60;
    std::uint32_t size = 256;
    std::array<std::uint32_t, 4> floats{0x3F000000u, 0x3A800000u, 0xBA800000u, 0x3C000000u};
    for (std::size_t i = 0; i < n; ++i) {
        const unsigned kind = rng() % 10;
        if (kind < 5) {
            offset += size;  // right after the last packet
        } else if (kind < 7) {
            offset += static_cast<std::uint64_t>(static_cast<std::int64_t>(rng() % 200001) - 100000);
        } else if (kind < 8) {
            offset = (std::uint64_t{rng()} << 32) | rng();  // far: coded raw
        }  // else the same offset
        if (sometimes(8)) size = sometimes(3) ? static_cast<std::uint32_t>(rng()) : size + rng() % 64;
        if (sometimes(40)) size = 0x80000000u + rng() % 1000;
        if (sometimes(20)) descriptor = static_cast<std::uint8_t>(rng());
        for (auto& f : floats) {
            if (sometimes(4)) f = sometimes(2) ? static_cast<std::uint32_t>(rng()) : f + rng() % 16;
        }
        std::uint8_t* p = out.data() + i * kSize;
        p[0] = descriptor;
        std::memcpy(p + 1, &offset, 8);
        std::memcpy(p + 9, &size, 4);
        std::memcpy(p + 13, floats.data(), 16);
    }
    return out;
}

// `records` (n of `rl` bytes) with the wave packets of `packets` (n of 29 bytes) placed at
// `at`, the bytes from `at` on moved back by 29 (extra bytes after the packet).
inline std::vector<std::uint8_t> with_wave_packets(std::span<const std::uint8_t> records, std::size_t rl,
                                                   std::size_t at, std::span<const std::uint8_t> packets) {
    const std::size_t n = records.size() / rl, out_rl = rl + 29;
    std::vector<std::uint8_t> out(n * out_rl);
    for (std::size_t i = 0; i < n; ++i) {
        const std::uint8_t* r = records.data() + i * rl;
        std::uint8_t* o = out.data() + i * out_rl;
        std::memcpy(o, r, at);
        std::memcpy(o + at, packets.data() + i * 29, 29);
        std::memcpy(o + at + 29, r + at, rl - at);
    }
    return out;
}

}  // namespace lidarscout::laz::codec_test
