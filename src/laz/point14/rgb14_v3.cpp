// RGB14: the colour codec (shared with RGBNIR14) and the item's layer.
#include "laz/point14/rgb14_v3.hpp"

#include <array>

#include "laz/chunk_decoder.hpp"
#include "laz/point14/rgb14_v3_state.hpp"
#include "laz/point14/symbols_v3.hpp"

namespace lidarscout::laz::point14 {
namespace {

// One byte: `prediction` plus a coded correction when its bit is set in `mask`, else `last`.
inline std::int32_t next_byte(ArithmeticDecoder& dec, SymbolModel& model, std::uint32_t mask, std::uint32_t bit,
                              std::int32_t prediction, std::int32_t last) {
    if (!(mask & bit)) return last;
    return wrap_byte(static_cast<std::int32_t>(dec.decode_symbol(model)) + prediction);
}

// Value, Models and read() come from the state shared with the encoder.
struct RgbCodec : RgbState {
    void write(std::uint8_t* item, const Value& v) const {
        store(item, v[0]);
        store(item + 2, v[1]);
        store(item + 4, v[2]);
    }

    void decode(ArithmeticDecoder& dec, Models& m, Value& v, const PointTrace&) const {
        const std::uint32_t mask = dec.decode_symbol(m.changed);
        const Value last = v;
        const std::int32_t red_low = next_byte(dec, m.bytes[0], mask, kRedLow, low(last[0]), low(last[0]));
        const std::int32_t red_high = next_byte(dec, m.bytes[1], mask, kRedHigh, high(last[0]), high(last[0]));
        v[0] = static_cast<std::uint16_t>(red_low | (red_high << 8));
        if (!(mask & kNotGrey)) {
            v[1] = v[2] = v[0];
            return;
        }
        // The low bytes first (green, then blue), then the high bytes: the stream's order.
        std::int32_t shift = red_low - low(last[0]);
        const std::int32_t green_low =
            next_byte(dec, m.bytes[2], mask, kGreenLow, clamp_byte(shift + low(last[1])), low(last[1]));
        const std::int32_t blue_low =
            next_byte(dec, m.bytes[4], mask, kBlueLow,
                      clamp_byte((shift + (green_low - low(last[1]))) / 2 + low(last[2])), low(last[2]));
        shift = red_high - high(last[0]);
        const std::int32_t green_high =
            next_byte(dec, m.bytes[3], mask, kGreenHigh, clamp_byte(shift + high(last[1])), high(last[1]));
        const std::int32_t blue_high =
            next_byte(dec, m.bytes[5], mask, kBlueHigh,
                      clamp_byte((shift + (green_high - high(last[1]))) / 2 + high(last[2])), high(last[2]));
        v[1] = static_cast<std::uint16_t>(green_low | (green_high << 8));
        v[2] = static_cast<std::uint16_t>(blue_low | (blue_high << 8));
    }
};

}  // namespace

PlacedLayer make_rgb_layer(std::span<const std::uint8_t> stream, const ItemSetup& setup) {
    return make_layer(stream, setup, RgbCodec{}, item_rule(setup.version), "RGB");
}

void add_rgb14_layers(const ItemSetup& setup, std::vector<PlacedLayer>& out) {
    if (setup.fields & fields::kRgb) out.push_back(make_rgb_layer(setup.layers[0], setup));
}

}  // namespace lidarscout::laz::point14
