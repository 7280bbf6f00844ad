// The RGB14 item of layered chunks, versions 3 and 4: the out-of-line parts of its state, decoder
// and encoder (see rgb14_v3.hpp).
#include "laz/items/point14/rgb14_v3.hpp"

#include <array>

#include "laz/chunk_decoder.hpp"

namespace lidarscout::laz::detail::point14 {

// ---- Decoder
// RGB14: the colour codec (shared with RGBNIR14) and the item's layer.
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

// ---- Encoder
// RGB14 encoding: the colour codec (shared with RGBNIR14).
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

}  // namespace lidarscout::laz::detail::point14
