// The wave packet codec shared by WAVEPACKET13 version 1 (point-wise chunks, formats 4 and 5) and
// WAVEPACKET14 versions 3 and 4 (layered chunks, formats 9 and 10): both code a packet the same
// way, and differ only in where the models live (one set per chunk, or one per scanner channel).
// A packet is the descriptor index, then the offset of its waveform data (the same as the last
// packet's, right after it, a coded 32-bit delta, or raw), its size, the return point location and
// the XYZ(t) direction, each predicted from the last packet's value (the floats as their bit
// patterns). The decoder and the encoder run the same code on the same models; the integer coder
// is IntegerDecompressor in the one and IntegerCompressor in the other.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>

#include "laz/arithmetic_decoder.hpp"
#include "laz/arithmetic_encoder.hpp"
#include "laz/arithmetic_models.hpp"
#include "laz/integer_compressor.hpp"
#include "laz/integer_decompressor.hpp"
#include "laz/items/item_common.hpp"

namespace lidarscout::laz::detail::wavepacket {

// ---- Symbols (the decoder and the encoder agree on them by construction)
// How the data offset follows from the last packet's.
enum OffsetKind : std::uint32_t { kSameOffset = 0, kAfterLast = 1, kCodedDelta = 2, kRawOffset = 3 };
inline constexpr std::uint32_t kOffsetKinds = 4;

inline constexpr std::size_t kSize = 29;  // the item: descriptor index, then the 28-byte packet

struct Packet {
    std::uint8_t descriptor = 0;
    std::uint64_t offset = 0;
    std::uint32_t size = 0;
    std::int32_t return_point = 0;      // float, predicted as its bit pattern
    std::array<std::int32_t, 3> xyz{};  // floats, likewise

    bool operator==(const Packet&) const = default;
};

inline Packet read_packet(const std::uint8_t* item) {
    Packet p;
    p.descriptor = item[0];
    p.offset = load<std::uint64_t>(item + 1);
    p.size = load<std::uint32_t>(item + 9);
    p.return_point = load<std::int32_t>(item + 13);
    for (int i = 0; i < 3; ++i) p.xyz[i] = load<std::int32_t>(item + 17 + 4 * i);
    return p;
}

inline void write_packet(std::uint8_t* item, const Packet& p) {
    item[0] = p.descriptor;
    store(item + 1, p.offset);
    store(item + 9, p.size);
    store(item + 13, p.return_point);
    for (int i = 0; i < 3; ++i) store(item + 17 + 4 * i, p.xyz[i]);
}

// ---- State shared by the decoder and the encoder
// The models of one context and the running offset state, in their start state when made.
template <class IntegerCoder>
struct Models {
    SymbolModel descriptor{256};
    std::array<SymbolModel, kOffsetKinds> offset_kind{SymbolModel(kOffsetKinds), SymbolModel(kOffsetKinds),
                                                      SymbolModel(kOffsetKinds), SymbolModel(kOffsetKinds)};
    IntegerCoder offset_delta{32};
    IntegerCoder size{32};
    IntegerCoder return_point{32};
    IntegerCoder xyz{32, 3};
    std::uint32_t last_kind = kSameOffset;  // selects the offset kind's model
    std::int32_t last_delta = 0;            // the last coded delta, the next one's prediction

    void begin(Packet&) {}  // (for the layered chunks' ChannelContexts)

    // Back to the start state (at the start of every chunk).
    void reset() {
        descriptor.reset();
        for (auto& m : offset_kind) m.reset();
        offset_delta.reset();
        size.reset();
        return_point.reset();
        xyz.reset();
        last_kind = kSameOffset;
        last_delta = 0;
    }
};

// ---- Decoder
// The packet after `last`, decoded in place.
inline void decode(ArithmeticDecoder& dec, Models<IntegerDecompressor>& m, Packet& p) {
    const Packet last = p;
    p.descriptor = static_cast<std::uint8_t>(dec.decode_symbol(m.descriptor));
    m.last_kind = dec.decode_symbol(m.offset_kind[m.last_kind]);
    switch (m.last_kind) {
        case kSameOffset: p.offset = last.offset; break;
        case kAfterLast: p.offset = last.offset + last.size; break;
        case kCodedDelta:
            m.last_delta = m.offset_delta.decompress(dec, m.last_delta);
            p.offset = last.offset + static_cast<std::uint64_t>(std::int64_t{m.last_delta});
            break;
        default: p.offset = dec.read_int64(); break;
    }
    p.size = static_cast<std::uint32_t>(m.size.decompress(dec, static_cast<std::int32_t>(last.size)));
    p.return_point = m.return_point.decompress(dec, last.return_point);
    for (std::uint32_t i = 0; i < 3; ++i) p.xyz[i] = m.xyz.decompress(dec, last.xyz[i], i);
}

// ---- Encoder
// How `now`'s offset is coded after `last`'s: LASzip's choice (the same, right after the last
// packet, a delta that fits 32 bits, else raw), except that "right after" is taken only when the
// decoder's sum gives the offset back (LASzip compares the 32-bit delta with the size as a
// signed number, which differs for sizes of 2 GiB and more).
inline std::uint32_t offset_kind(const Packet& last, const Packet& now) {
    const std::uint64_t delta = now.offset - last.offset;
    if (delta == 0) return kSameOffset;
    if (delta == last.size) return kAfterLast;
    const auto signed_delta = static_cast<std::int64_t>(delta);
    if (signed_delta == static_cast<std::int32_t>(signed_delta)) return kCodedDelta;
    return kRawOffset;
}

// Codes `now` after `last`.
inline void encode(ArithmeticEncoder& enc, Models<IntegerCompressor>& m, const Packet& last, const Packet& now) {
    enc.encode_symbol(m.descriptor, now.descriptor);
    const std::uint32_t kind = offset_kind(last, now);
    enc.encode_symbol(m.offset_kind[m.last_kind], kind);
    m.last_kind = kind;
    if (kind == kCodedDelta) {
        const auto delta = static_cast<std::int32_t>(static_cast<std::int64_t>(now.offset - last.offset));
        m.offset_delta.compress(enc, m.last_delta, delta);
        m.last_delta = delta;
    } else if (kind == kRawOffset) {
        enc.write_int64(now.offset);
    }
    m.size.compress(enc, static_cast<std::int32_t>(last.size), static_cast<std::int32_t>(now.size));
    m.return_point.compress(enc, last.return_point, now.return_point);
    for (std::uint32_t i = 0; i < 3; ++i) m.xyz.compress(enc, last.xyz[i], now.xyz[i], i);
}

}  // namespace lidarscout::laz::detail::wavepacket
