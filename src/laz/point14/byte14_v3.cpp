// BYTE14: the per-byte codec and its passes.
#include "laz/point14/byte14_v3.hpp"

#include "laz/chunk_decoder.hpp"
#include "laz/point14/byte14_v3_state.hpp"

namespace lidarscout::laz::point14 {
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

}  // namespace lidarscout::laz::point14
