// RGBNIR14 encoding: the NIR codec; the colour layer comes from rgb14_v3_encoder.
#include "laz/point14/rgbnir14_v3_encoder.hpp"

#include "laz/point14/rgb14_v3_encoder.hpp"
#include "laz/point14/rgbnir14_v3_state.hpp"

namespace lidarscout::laz::point14 {
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

}  // namespace lidarscout::laz::point14
