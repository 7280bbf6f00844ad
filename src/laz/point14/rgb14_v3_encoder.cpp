// RGB14 encoding: the colour codec (shared with RGBNIR14).
#include "laz/point14/rgb14_v3_encoder.hpp"

#include <array>

#include "laz/point14/rgb14_v3_state.hpp"
#include "laz/point14/symbols_v3.hpp"

namespace lidarscout::laz::point14 {
namespace {

// Value, Models and read() come from the state shared with the decoder.
struct RgbEncoder : RgbState {
    // The layer counts as changed whenever the symbol is not 0, i.e. also for a colour that
    // stays the same but is not grey (LASzip's rule).
    bool encode(ArithmeticEncoder& enc, Models& m, Value& last, const Value& now, const PointTrace&) const {
        const bool grey = low(now[0]) == low(now[1]) && low(now[0]) == low(now[2]) && high(now[0]) == high(now[1]) &&
                          high(now[0]) == high(now[2]);
        const std::uint32_t mask =
            (low(now[0]) != low(last[0]) ? kRedLow : 0u) | (high(now[0]) != high(last[0]) ? kRedHigh : 0u) |
            (low(now[1]) != low(last[1]) ? kGreenLow : 0u) | (high(now[1]) != high(last[1]) ? kGreenHigh : 0u) |
            (low(now[2]) != low(last[2]) ? kBlueLow : 0u) | (high(now[2]) != high(last[2]) ? kBlueHigh : 0u) |
            (grey ? 0u : kNotGrey);
        enc.encode_symbol(m.changed, mask);
        std::int32_t shift_low = 0;
        std::int32_t shift_high = 0;
        if (mask & kRedLow) {
            shift_low = low(now[0]) - low(last[0]);
            enc.encode_symbol(m.bytes[0], wrap_byte(shift_low));
        }
        if (mask & kRedHigh) {
            shift_high = high(now[0]) - high(last[0]);
            enc.encode_symbol(m.bytes[1], wrap_byte(shift_high));
        }
        if (mask & kNotGrey) {
            if (mask & kGreenLow) {
                const std::int32_t prediction = clamp_byte(shift_low + low(last[1]));
                enc.encode_symbol(m.bytes[2], wrap_byte(low(now[1]) - prediction));
            }
            if (mask & kBlueLow) {
                const std::int32_t shift = (shift_low + low(now[1]) - low(last[1])) / 2;
                enc.encode_symbol(m.bytes[4], wrap_byte(low(now[2]) - clamp_byte(shift + low(last[2]))));
            }
            if (mask & kGreenHigh) {
                const std::int32_t prediction = clamp_byte(shift_high + high(last[1]));
                enc.encode_symbol(m.bytes[3], wrap_byte(high(now[1]) - prediction));
            }
            if (mask & kBlueHigh) {
                const std::int32_t shift = (shift_high + high(now[1]) - high(last[1])) / 2;
                enc.encode_symbol(m.bytes[5], wrap_byte(high(now[2]) - clamp_byte(shift + high(last[2]))));
            }
        }
        last = now;
        return mask != 0;
    }
};

}  // namespace

std::unique_ptr<LayerEncoder> make_rgb_encoder(const ItemEncodeSetup& setup) {
    return make_layer_encoder(setup, RgbEncoder{}, ContextRule::kItemV3);
}

void add_rgb14_encoders(const ItemEncodeSetup& setup, std::vector<std::unique_ptr<LayerEncoder>>& out) {
    out.push_back(make_rgb_encoder(setup));
}

}  // namespace lidarscout::laz::point14
