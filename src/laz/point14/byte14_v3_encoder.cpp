// BYTE14 encoding: the per-byte codec.
#include "laz/point14/byte14_v3_encoder.hpp"

#include "laz/point14/byte14_v3_state.hpp"

namespace lidarscout::laz::point14 {
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

}  // namespace lidarscout::laz::point14
