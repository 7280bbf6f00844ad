// WAVEPACKET13 v1: chunk start state and per-point decoding (formats with waveforms are
// rare, so this item is not inlined into the point loop).
#include "laz/items/point10/wavepacket13_v1.hpp"

namespace lidarscout::laz::detail::point10 {
namespace {

// How the data offset follows from the last packet.
constexpr std::uint32_t kOffsetSame = 0;
constexpr std::uint32_t kOffsetAfterLast = 1;
constexpr std::uint32_t kOffsetDelta = 2;

}  // namespace

Wavepacket13DecoderV1::Wavepacket13DecoderV1() = default;

Wavepacket13DecoderV1::Packet Wavepacket13DecoderV1::load_packet(const std::uint8_t* p) {
    Packet packet;
    packet.offset = load<std::uint64_t>(p);
    packet.size = load<std::uint32_t>(p + 8);
    packet.return_point = load<std::int32_t>(p + 12);
    for (int i = 0; i < 3; ++i) packet.xyz[i] = load<std::int32_t>(p + 16 + 4 * i);
    return packet;
}

void Wavepacket13DecoderV1::store_packet(const Packet& packet, std::uint8_t* p) {
    store(p, packet.offset);
    store(p + 8, packet.size);
    store(p + 12, packet.return_point);
    for (int i = 0; i < 3; ++i) store(p + 16 + 4 * i, packet.xyz[i]);
}

void Wavepacket13DecoderV1::init(const std::uint8_t* first) {
    last_ = load_packet(first + 1);
    last_offset_delta_ = 0;
    last_offset_kind_ = 0;
    descriptor_model_.reset();
    for (auto& m : offset_kind_models_) m.reset();
    offset_delta_.reset();
    size_.reset();
    return_point_.reset();
    xyz_.reset();
}

void Wavepacket13DecoderV1::decode(ArithmeticDecoder& dec, std::uint8_t* out) {
    out[0] = static_cast<std::uint8_t>(dec.decode_symbol(descriptor_model_));

    Packet next;
    last_offset_kind_ = dec.decode_symbol(offset_kind_models_[last_offset_kind_]);
    switch (last_offset_kind_) {
        case kOffsetSame: next.offset = last_.offset; break;
        case kOffsetAfterLast: next.offset = last_.offset + last_.size; break;
        case kOffsetDelta:
            last_offset_delta_ = offset_delta_.decompress(dec, last_offset_delta_);
            next.offset = last_.offset + static_cast<std::uint64_t>(std::int64_t{last_offset_delta_});
            break;
        default: next.offset = dec.read_int64(); break;
    }
    next.size = static_cast<std::uint32_t>(size_.decompress(dec, static_cast<std::int32_t>(last_.size)));
    next.return_point = return_point_.decompress(dec, last_.return_point);
    for (std::uint32_t i = 0; i < 3; ++i) next.xyz[i] = xyz_.decompress(dec, last_.xyz[i], i);

    store_packet(next, out + 1);
    last_ = next;
}

}  // namespace lidarscout::laz::detail::point10
