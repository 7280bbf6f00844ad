// The WAVEPACKET13 item, version 1: its per-point decoding and encoding (out of line: formats with
// waveforms are rare; see wavepacket13_v1.hpp).
#include "laz/items/point10/wavepacket13_v1.hpp"

namespace lidarscout::laz::detail::point10 {

void Wavepacket13DecoderV1::decode(ArithmeticDecoder& dec, std::uint8_t* out) {
    wavepacket::decode(dec, models_, last_);
    wavepacket::write_packet(out, last_);
}

void Wavepacket13EncoderV1::encode(ArithmeticEncoder& enc, const std::uint8_t* item) {
    const wavepacket::Packet now = wavepacket::read_packet(item);
    wavepacket::encode(enc, models_, last_, now);
    last_ = now;
}

}  // namespace lidarscout::laz::detail::point10
