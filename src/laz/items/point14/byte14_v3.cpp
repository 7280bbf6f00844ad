// The BYTE14 item (extra bytes) of layered chunks, versions 3 and 4: the out-of-line parts of its state, decoder
// and encoder (see byte14_v3.hpp).
#include "laz/items/point14/byte14_v3.hpp"

#include "laz/chunk_decoder.hpp"

namespace lidarscout::laz::detail::point14 {

// ---- Decoder
// BYTE14: the per-byte codec and its passes.
namespace {

// Value, Models and read() come from the state shared with the encoder.
struct ByteCodec : Byte14State {
    void write(std::uint8_t* item, Value v) const { item[offset] = v; }
    void decode(ArithmeticDecoder& dec, Models& m, Value& v, const PointTrace&) const {
        v = wrap_byte(static_cast<std::int32_t>(dec.decode_symbol(m.difference) + v));
    }
};

}  // namespace

void add_byte14_layers(const ItemSetup& setup, std::vector<PlacedLayer>& out) {
    if (!(setup.fields & fields::kExtraBytes)) return;
    const ContextRule rule = item_rule(setup.version);
    for (std::size_t i = 0; i < setup.layers.size(); ++i) {
        out.push_back(make_layer(setup.layers[i], setup, ByteCodec{{i}}, rule, "extra bytes"));
    }
}

// ---- Encoder
// BYTE14 encoding: the per-byte codec.
namespace {

// Value, Models and read() come from the state shared with the decoder.
struct ByteEncoder : Byte14State {
    bool encode(ArithmeticEncoder& enc, Models& m, Value& last, Value now, const PointTrace&) const {
        enc.encode_symbol(m.difference, wrap_byte(now - last));
        return replace_last(last, now);
    }
};

}  // namespace

void add_byte14_encoders(const ItemEncodeSetup& setup, std::size_t size,
                         std::vector<std::unique_ptr<LayerEncoder>>& out) {
    for (std::size_t i = 0; i < size; ++i) {
        out.push_back(make_layer_encoder(setup, ByteEncoder{{i}}, ContextRule::kItemV3));
    }
}

}  // namespace lidarscout::laz::detail::point14
