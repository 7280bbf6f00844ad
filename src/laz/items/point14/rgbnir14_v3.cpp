// The RGBNIR14 item of layered chunks, versions 3 and 4: the out-of-line parts of its state, decoder
// and encoder (see rgbnir14_v3.hpp).
#include "laz/items/point14/rgbnir14_v3.hpp"

#include "laz/chunk_decoder.hpp"
#include "laz/items/point14/rgb14_v3.hpp"

namespace lidarscout::laz::detail::point14 {

// ---- Decoder
// RGBNIR14: the NIR codec; the colour layer comes from rgb14_v3.
namespace {

// Value, Models and read() come from the state shared with the encoder.
struct NirCodec : NirState {
    void write(std::uint8_t* item, Value v) const { store(item + kNirOffset, v); }

    void decode(ArithmeticDecoder& dec, Models& m, Value& v, const PointTrace&) const {
        const std::uint32_t mask = dec.decode_symbol(m.changed);
        std::uint32_t lo = v & 0xFFu;
        std::uint32_t hi = v >> 8;
        if (mask & 1u) lo = wrap_byte(static_cast<std::int32_t>(dec.decode_symbol(m.bytes[0]) + lo));
        if (mask & 2u) hi = wrap_byte(static_cast<std::int32_t>(dec.decode_symbol(m.bytes[1]) + hi));
        v = static_cast<Value>(lo | (hi << 8));
    }
};

}  // namespace

void add_rgbnir14_layers(const ItemSetup& setup, std::vector<PlacedLayer>& out) {
    if (setup.fields & fields::kRgb) out.push_back(make_rgb_layer(setup.layers[0], setup));
    if (setup.fields & fields::kNir) {
        out.push_back(make_layer(setup.layers[1], setup, NirCodec{}, item_rule(setup.version), "NIR"));
    }
}

// ---- Encoder
// RGBNIR14 encoding: the NIR codec; the colour layer comes from rgb14_v3_encoder.
namespace {

// Value, Models and read() come from the state shared with the decoder.
struct NirEncoder : NirState {
    bool encode(ArithmeticEncoder& enc, Models& m, Value& last, Value now, const PointTrace&) const {
        const std::int32_t lo = now & 0xFF, last_lo = last & 0xFF;
        const std::int32_t hi = now >> 8, last_hi = last >> 8;
        const std::uint32_t mask = (lo != last_lo ? 1u : 0u) | (hi != last_hi ? 2u : 0u);
        enc.encode_symbol(m.changed, mask);
        if (mask & 1u) enc.encode_symbol(m.bytes[0], wrap_byte(lo - last_lo));
        if (mask & 2u) enc.encode_symbol(m.bytes[1], wrap_byte(hi - last_hi));
        last = now;
        return mask != 0;
    }
};

}  // namespace

void add_rgbnir14_encoders(const ItemEncodeSetup& setup, std::vector<std::unique_ptr<LayerEncoder>>& out) {
    out.push_back(make_rgb_encoder(setup));
    out.push_back(make_layer_encoder(setup, NirEncoder{}, ContextRule::kItemV3));
}

}  // namespace lidarscout::laz::detail::point14
