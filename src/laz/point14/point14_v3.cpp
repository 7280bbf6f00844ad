// POINT14 layers: the returns/XY/Z pass and the codecs of classification, flags, intensity,
// scan angle, user data and point source ID (GPS time has its own file).
#include "laz/point14/point14_v3.hpp"


#include "laz/chunk_decoder.hpp"
#include "laz/point14/gps_time14_v3.hpp"
#include "laz/point14/symbols_v3.hpp"

namespace lidarscout::laz::point14 {
namespace {

namespace f = point14_field;

// ---- codecs of the layers after returns/XY/Z ---------------------------------------------

// Each codec takes its Value, Models and read() from the state it shares with the encoder
// (point14_v3_state.hpp) and adds how the value is decoded and stored.

struct ClassificationCodec : ClassificationState {
    void write(std::uint8_t* item, Value v) const { item[f::kClassification] = v; }
    void decode(ArithmeticDecoder& dec, Models& m, Value& v, const PointTrace& t) const {
        const std::uint32_t slot = ((v & 0x1Fu) << 1) | (t.return_kind == 3 ? 1u : 0u);
        v = static_cast<Value>(dec.decode_symbol(m.by_last[slot]));
    }
};

// The flag bits go back to their record positions (see FlagsState), only those wanted.
struct FlagsCodec : FlagsState {
    std::uint8_t record_mask;  // record bits the caller wants from this layer

    void write(std::uint8_t* item, Value v) const {
        const std::uint8_t bits = static_cast<std::uint8_t>((v & 0x0Fu) | ((v & 0x30u) << 2));
        item[f::kFlags] = static_cast<std::uint8_t>((item[f::kFlags] & ~record_mask) | (bits & record_mask));
    }
    void decode(ArithmeticDecoder& dec, Models& m, Value& v, const PointTrace&) const {
        v = static_cast<Value>(dec.decode_symbol(m.by_last[v]));
    }
};

struct IntensityCodec : IntensityState<IntegerDecompressor> {
    void write(std::uint8_t* item, Value v) const { store(item + f::kIntensity, v); }
    void decode(ArithmeticDecoder& dec, Models& m, Value& v, const PointTrace& t) const {
        const std::uint32_t slot = (std::uint32_t{t.return_kind} << 1) | (t.gps_time_changed() ? 1u : 0u);
        v = static_cast<Value>(m.intensity.decompress(dec, m.by_kind[slot], t.return_kind));
        m.by_kind[slot] = v;
    }
};

struct ScanAngleCodec : ScanAngleState<IntegerDecompressor> {
    void write(std::uint8_t* item, Value v) const { store(item + f::kScanAngle, v); }
    void decode(ArithmeticDecoder& dec, Models& m, Value& v, const PointTrace& t) const {
        if (t.changed & PointTrace::kScanAngleChanged) {
            v = static_cast<Value>(m.coder.decompress(dec, v, t.gps_time_changed() ? 1u : 0u));
        }
    }
};

struct UserDataCodec : UserDataState {
    void write(std::uint8_t* item, Value v) const { item[f::kUserData] = v; }
    void decode(ArithmeticDecoder& dec, Models& m, Value& v, const PointTrace&) const {
        v = static_cast<Value>(dec.decode_symbol(m.by_last[v >> 2]));
    }
};

struct PointSourceCodec : PointSourceState<IntegerDecompressor> {
    void write(std::uint8_t* item, Value v) const { store(item + f::kPointSource, v); }
    void decode(ArithmeticDecoder& dec, Models& m, Value& v, const PointTrace& t) const {
        if (t.changed & PointTrace::kPointSourceChanged) v = static_cast<Value>(m.coder.decompress(dec, v));
    }
};

}  // namespace

// ---- returns/XY/Z ----------------------------------------------------------------------

ReturnsXyzLayer::ReturnsXyzLayer(const ItemSetup& setup, bool write_returns)
    : xy_decoder_(setup.layers[0]),
      z_decoder_(setup.layers[1]),
      z_coded_(!setup.layers[1].empty()),
      write_returns_(write_returns),
      hand_on_channel_(setup.version >= 4) {
    contexts_.start(setup.first_channel, Value::read(setup.first), true);
}

void ReturnsXyzLayer::store(std::uint8_t* item, const Value& v, std::uint32_t channel) const {
    point14::store(item + f::kX, v.x);
    point14::store(item + f::kY, v.y);
    point14::store(item + f::kZ, v.z);
    if (write_returns_) {
        item[f::kReturns] = static_cast<std::uint8_t>(v.return_number | (v.returns << 4));
        item[f::kFlags] = static_cast<std::uint8_t>(channel << 4);
    } else {
        item[f::kFlags] = 0;  // the flags layer (if wanted) fills in its bits after this pass
    }
}

void ReturnsXyzLayer::write_first(std::uint8_t* item) { store(item, contexts_.value(), contexts_.channel()); }

void ReturnsXyzLayer::decode_returns(ArithmeticDecoder& dec, Models& m, Value& last, std::uint32_t changed,
                                     bool time_changed) {
    if (changed & kReturnsChanged) last.returns = dec.decode_symbol(m.returns[last.returns]);
    std::uint32_t& r = last.return_number;
    switch (changed & kReturnStepMask) {
        case 0: break;
        case 1: r = (r + 1) & 15u; break;
        case 2: r = (r + 15) & 15u; break;
        default:
            if (time_changed) {
                r = dec.decode_symbol(m.return_number[r]);
            } else {
                r = (r + dec.decode_symbol(m.return_step) + 2) & 15u;
            }
    }
}

void ReturnsXyzLayer::decode_xy(ArithmeticDecoder& dec, Models& m, Value& last, bool time_changed) {
    const std::uint32_t single = last.returns == 1 ? 1u : 0u;
    const std::uint32_t median =
        (std::uint32_t{kReturnClass[last.returns][last.return_number]} << 1) | (time_changed ? 1u : 0u);
    const std::int32_t dx = m.dx.decompress(dec, m.x_median[median].median(), single);
    last.x = add_wrapping(last.x, dx);
    m.x_median[median].add(dx);
    const std::int32_t dy =
        m.dy.decompress(dec, m.y_median[median].median(), single + size_context(m.dx.last_class(), 20));
    last.y = add_wrapping(last.y, dy);
    m.y_median[median].add(dy);
}

void ReturnsXyzLayer::decode_z(ArithmeticDecoder& dec, Models& m, Value& last) {
    const std::uint32_t single = last.returns == 1 ? 1u : 0u;
    const std::uint32_t level = return_level(last.returns, last.return_number);
    const std::uint32_t k = (m.dx.last_class() + m.dy.last_class()) / 2;
    last.z = m.z.decompress(dec, m.z_by_level[level], single + size_context(k, 18));
    m.z_by_level[level] = last.z;
}

// Z is decoded in the same loop as returns/XY: it needs the point's return level and X/Y
// corrector sizes, and is always wanted.
[[gnu::flatten]] void ReturnsXyzLayer::decode(PointTrace* trace, std::size_t count, std::uint8_t* item,
                                              std::size_t stride) {
    ArithmeticDecoder dec = xy_decoder_;  // local copies the compiler can keep in registers
    ArithmeticDecoder z_dec = z_decoder_;
    Models* m = &contexts_.models();
    Value* last = &contexts_.value();
    for (std::size_t i = 0; i < count; ++i, item += stride) {
        const std::uint32_t last_kind = (last->return_number == 1 ? 1u : 0u) |
                                        (last->return_number >= last->returns ? 2u : 0u) |
                                        (last->gps_time_changed ? 4u : 0u);
        const std::uint32_t changed = dec.decode_symbol(m->changed[last_kind]);
        std::uint32_t item_context = hand_on_channel_ ? contexts_.channel() : 0;
        if (changed & kChannelChanged) [[unlikely]] {
            const std::uint32_t step = dec.decode_symbol(m->channel_step);
            contexts_.select((contexts_.channel() + step + 1) & 3u);
            m = &contexts_.models();
            last = &contexts_.value();
            item_context = contexts_.channel();
        }
        const bool time_changed = (changed & (std::uint32_t{PointTrace::kGpsTimeChanged} << kChangedShift)) != 0;
        decode_returns(dec, *m, *last, changed, time_changed);
        decode_xy(dec, *m, *last, time_changed);
        last->gps_time_changed = time_changed;
        if (z_coded_) decode_z(z_dec, *m, *last);

        const std::uint32_t r = last->return_number;
        PointTrace& t = trace[i];
        t.channel = static_cast<std::uint8_t>(contexts_.channel());
        t.item_context = static_cast<std::uint8_t>(item_context);
        t.changed = static_cast<std::uint8_t>((changed >> kChangedShift) & 7u);
        t.return_kind = static_cast<std::uint8_t>((r == 1 ? 2u : 0u) | (r >= last->returns ? 1u : 0u));
        store(item, *last, t.channel);
    }
    xy_decoder_ = dec;
    z_decoder_ = z_dec;
}

std::unique_ptr<ReturnsXyzLayer> make_returns_xyz_layer(const ItemSetup& setup) {
    return std::make_unique<ReturnsXyzLayer>(setup, (setup.fields & fields::kReturns) != 0);
}

// ---- the other layers ------------------------------------------------------------------

void add_point14_layers(const ItemSetup& setup, std::vector<PlacedLayer>& out) {
    const auto& layers = setup.layers;
    const std::uint32_t want = setup.fields;
    auto add = [&](std::size_t layer, auto codec, const char* name) {
        out.push_back(make_layer(layers[layer], setup, codec, ContextRule::kPoint14, name));
    };
    if (want & fields::kClassification) add(2, ClassificationCodec{}, "classification");
    const std::uint8_t flag_bits = static_cast<std::uint8_t>((want & fields::kReturns ? 0xC0u : 0u) |
                                                             (want & fields::kClassification ? 0x0Fu : 0u));
    if (flag_bits) add(3, FlagsCodec{{}, flag_bits}, "flags");
    if (want & fields::kIntensity) add(4, IntensityCodec{}, "intensity");
    if (want & fields::kScanAngle) add(5, ScanAngleCodec{}, "scan angle");
    if (want & fields::kUserData) add(6, UserDataCodec{}, "user data");
    if (want & fields::kPointSource) add(7, PointSourceCodec{}, "point source ID");
    if (want & fields::kGpsTime) out.push_back(make_gps_time14_layer(layers[8], setup));
}

}  // namespace lidarscout::laz::point14
