// The WAVEPACKET13 item, version 1 (LAS formats 4 and 5 in point-wise chunks): one file set
// (wavepacket13_v1.hpp/.cpp) holds this item version's decoder and encoder; the packet codec they
// run is shared with WAVEPACKET14 (items/wavepacket_codec.hpp). One set of models per chunk, the
// last packet the prediction of the next.
#pragma once

#include <cstdint>

#include "laz/items/wavepacket_codec.hpp"

namespace lidarscout::laz::detail::point10 {

// ---- State shared by the decoder and the encoder
// The last packet and the models, reset at chunk start.
template <class IntegerCoder>
class Wavepacket13StateV1 {
public:
    static constexpr std::size_t kSize = wavepacket::kSize;

    // Starts a chunk whose first (raw) packet is at `first`.
    void init(const std::uint8_t* first) {
        last_ = wavepacket::read_packet(first);
        models_.reset();
    }

protected:
    wavepacket::Packet last_;
    wavepacket::Models<IntegerCoder> models_;
};

// ---- Decoder
// Formats with waveforms are rare, so this item is not inlined into the point loop.
class Wavepacket13DecoderV1 : public Wavepacket13StateV1<IntegerDecompressor> {
public:
    void decode(ArithmeticDecoder& dec, std::uint8_t* out);
};

// ---- Encoder
// The mirror of the decoder: each packet coded after the last.
class Wavepacket13EncoderV1 : public Wavepacket13StateV1<IntegerCompressor> {
public:
    void encode(ArithmeticEncoder& enc, const std::uint8_t* item);
};

}  // namespace lidarscout::laz::detail::point10
