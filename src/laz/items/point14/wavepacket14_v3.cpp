// WAVEPACKET14: the layer codecs (decoder and encoder) around the shared packet codec.
#include "laz/items/point14/wavepacket14_v3.hpp"

#include "laz/chunk_decoder.hpp"

namespace lidarscout::laz::detail::point14 {
namespace {

// ---- State shared by the decoder and the encoder: the value and how it is read from a raw item.
template <class IntegerCoder>
struct WavepacketState {
    using Value = wavepacket::Packet;
    using Models = wavepacket::Models<IntegerCoder>;

    Value read(const std::uint8_t* item) const { return wavepacket::read_packet(item); }
};

// ---- Decoder
struct WavepacketCodec : WavepacketState<IntegerDecompressor> {
    void write(std::uint8_t* item, const Value& p) const { wavepacket::write_packet(item, p); }
    void decode(ArithmeticDecoder& dec, Models& m, Value& v, const PointTrace&) const { wavepacket::decode(dec, m, v); }
};

// ---- Encoder
struct WavepacketEncoder : WavepacketState<IntegerCompressor> {
    bool encode(ArithmeticEncoder& enc, Models& m, Value& last, const Value& now, const PointTrace&) const {
        wavepacket::encode(enc, m, last, now);
        return replace_last(last, now);
    }
};

}  // namespace

void add_wavepacket14_layers(const ItemSetup& setup, std::vector<PlacedLayer>& out) {
    if (!(setup.fields & fields::kWavepacket)) return;
    out.push_back(make_layer(setup.layers[0], setup, WavepacketCodec{}, item_rule(setup.version), "wave packet"));
}

void add_wavepacket14_encoders(const ItemEncodeSetup& setup, std::vector<std::unique_ptr<LayerEncoder>>& out) {
    out.push_back(make_layer_encoder(setup, WavepacketEncoder{}, ContextRule::kItemV3));
}

}  // namespace lidarscout::laz::detail::point14
