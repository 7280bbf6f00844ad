// RGBNIR14: the NIR codec; the colour layer comes from rgb14_v3.
#include "laz/point14/rgbnir14_v3.hpp"

#include "laz/chunk_decoder.hpp"
#include "laz/point14/rgb14_v3.hpp"
#include "laz/point14/rgbnir14_v3_state.hpp"

namespace lidarscout::laz::point14 {
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

}  // namespace lidarscout::laz::point14
