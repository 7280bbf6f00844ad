// The POINT14 item of layered chunks, versions 3 and 4: the out-of-line parts of its state, decoder
// and encoder (see point14_v3.hpp).
#include "laz/items/point14/point14_v3.hpp"

#include "laz/chunk_decoder.hpp"
#include "laz/items/point14/gps_time14_v3.hpp"

namespace lidarscout::laz::detail::point14 {

// ---- Decoder
// POINT14 layers: the returns/XY/Z pass and the codecs of classification, flags, intensity,
// scan angle, user data and point source ID (GPS time has its own file).
namespace {

namespace f = point14_field;

// ---- codecs of the layers after returns/XY/Z ---------------------------------------------

// Each codec takes its Value, Models and read() from the state it shares with the encoder
// (point14_v3.hpp) and adds how the value is decoded and stored.

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
    detail::store(item + f::kX, v.x);
    detail::store(item + f::kY, v.y);
    detail::store(item + f::kZ, v.z);
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
        const std::uint32_t changed = dec.decode_likely_symbol(m->changed[last_kind]);
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
                                                             (want & fields::kClassFlags ? 0x0Fu : 0u));
    if (flag_bits) add(3, FlagsCodec{{}, flag_bits}, "flags");
    if (want & fields::kIntensity) add(4, IntensityCodec{}, "intensity");
    if (want & fields::kScanAngle) add(5, ScanAngleCodec{}, "scan angle");
    if (want & fields::kUserData) add(6, UserDataCodec{}, "user data");
    if (want & fields::kPointSource) add(7, PointSourceCodec{}, "point source ID");
    if (want & fields::kGpsTime) out.push_back(make_gps_time14_layer(layers[8], setup));
}

// ---- Encoder
// POINT14 version 3 encoding: the returns/XY/Z pass and the codecs of classification, flags,
// intensity, scan angle, user data and point source ID (GPS time has its own file).
namespace {

namespace f = point14_field;

std::int32_t subtract_wrapping(std::int32_t a, std::int32_t b) {
    return static_cast<std::int32_t>(static_cast<std::uint32_t>(a) - static_cast<std::uint32_t>(b));
}

// ---- codecs of the layers after returns/XY/Z ---------------------------------------------

// Each codec takes its Value, Models and read() from the state it shares with the decoder
// (point14_v3.hpp) and adds how a value is coded.

struct ClassificationEncoder : ClassificationState {
    bool encode(ArithmeticEncoder& enc, Models& m, Value& last, Value now, const PointTrace& t) const {
        const std::uint32_t slot = ((last & 0x1Fu) << 1) | (t.return_kind == 3 ? 1u : 0u);
        enc.encode_symbol(m.by_last[slot], now);
        return replace_last(last, now);
    }
};

struct FlagsEncoder : FlagsState {
    bool encode(ArithmeticEncoder& enc, Models& m, Value& last, Value now, const PointTrace&) const {
        enc.encode_symbol(m.by_last[last], now);
        return replace_last(last, now);
    }
};

struct IntensityEncoder : IntensityState<IntegerCompressor> {
    bool encode(ArithmeticEncoder& enc, Models& m, Value& last, Value now, const PointTrace& t) const {
        const std::uint32_t slot = (std::uint32_t{t.return_kind} << 1) | (t.gps_time_changed() ? 1u : 0u);
        m.intensity.compress(enc, m.by_kind[slot], now, t.return_kind);
        m.by_kind[slot] = now;
        return replace_last(last, now);
    }
};

struct ScanAngleEncoder : ScanAngleState<IntegerCompressor> {
    bool encode(ArithmeticEncoder& enc, Models& m, Value& last, Value now, const PointTrace& t) const {
        if (!(t.changed & PointTrace::kScanAngleChanged)) return false;
        m.coder.compress(enc, last, now, t.gps_time_changed() ? 1u : 0u);
        last = now;
        return true;
    }
};

struct UserDataEncoder : UserDataState {
    bool encode(ArithmeticEncoder& enc, Models& m, Value& last, Value now, const PointTrace&) const {
        enc.encode_symbol(m.by_last[last >> 2], now);
        return replace_last(last, now);
    }
};

struct PointSourceEncoder : PointSourceState<IntegerCompressor> {
    bool encode(ArithmeticEncoder& enc, Models& m, Value& last, Value now, const PointTrace& t) const {
        if (!(t.changed & PointTrace::kPointSourceChanged)) return false;
        m.coder.compress(enc, last, now);
        last = now;
        return true;
    }
};

}  // namespace

// ---- returns/XY/Z ----------------------------------------------------------------------

ReturnsXyzEncoder::Value ReturnsXyzEncoder::read(const std::uint8_t* item) {
    Value v{ReturnsXyzValue::read(item)};
    v.gps_time = load<double>(item + f::kGpsTime);
    v.scan_angle = load<std::int16_t>(item + f::kScanAngle);
    v.point_source = load<std::uint16_t>(item + f::kPointSource);
    return v;
}

ReturnsXyzEncoder::ReturnsXyzEncoder(const ItemEncodeSetup& setup) {
    xy_.start(xy_bytes_);
    z_.start(z_bytes_);
    contexts_.start(setup.first_channel, read(setup.first), true);
}

void ReturnsXyzEncoder::finish() {
    xy_.done();
    z_.done();
}

inline void ReturnsXyzEncoder::encode_point(const std::uint8_t* item, PointTrace& trace) {
    const Value now = read(item);
    const std::uint32_t channel = point14_channel(item);

    // The change symbol is coded in the models of the channel of the last point, in the
    // context of that point's return kind.
    const Value& before = contexts_.value();
    const std::uint32_t last_kind = (before.return_number == 1 ? 1u : 0u) |
                                    (before.return_number >= before.returns ? 2u : 0u) |
                                    (before.gps_time_changed ? 4u : 0u);
    Models& before_models = contexts_.models();
    const std::uint32_t last_channel = contexts_.channel();
    std::uint32_t item_context = 0;  // version 3 hands on the channel only where it changes
    if (channel != last_channel) [[unlikely]] {
        contexts_.select(channel);
        item_context = channel;
    }
    // What the point is compared with: the last point of its own channel (a new channel
    // starts from the last point of the previous one).
    Value& last = contexts_.value();
    Models& m = contexts_.models();

    const bool time_changed = now.gps_time != last.gps_time;
    const auto flag = [](bool set, std::uint32_t bit) { return set ? bit : 0u; };
    const std::uint32_t traced = flag(now.point_source != last.point_source, PointTrace::kPointSourceChanged) |
                                 flag(time_changed, PointTrace::kGpsTimeChanged) |
                                 flag(now.scan_angle != last.scan_angle, PointTrace::kScanAngleChanged);
    std::uint32_t changed = flag(channel != last_channel, kChannelChanged) | (traced << kChangedShift) |
                            flag(now.returns != last.returns, kReturnsChanged);
    const std::uint32_t r = now.return_number;
    const std::uint32_t last_r = last.return_number;
    if (r != last_r) {
        if (r == ((last_r + 1) & 15u)) {
            changed |= 1u;
        } else if (r == ((last_r + 15) & 15u)) {
            changed |= 2u;
        } else {
            changed |= 3u;
        }
    }
    xy_.encode_symbol(before_models.changed[last_kind], changed);
    if (changed & kChannelChanged) {
        xy_.encode_symbol(before_models.channel_step, (channel - last_channel - 1) & 3u);
    }
    if (changed & kReturnsChanged) xy_.encode_symbol(m.returns[last.returns], now.returns);
    if ((changed & kReturnStepMask) == 3u) {
        if (time_changed) {
            xy_.encode_symbol(m.return_number[last_r], r);
        } else {
            xy_.encode_symbol(m.return_step, (r - last_r - 2) & 15u);
        }
    }

    const std::uint32_t n = now.returns;
    const std::uint32_t single = n == 1 ? 1u : 0u;
    const std::uint32_t median = (std::uint32_t{kReturnClass[n][r]} << 1) | (time_changed ? 1u : 0u);
    const std::int32_t dx = subtract_wrapping(now.x, last.x);
    m.dx.compress(xy_, m.x_median[median].median(), dx, single);
    m.x_median[median].add(dx);
    const std::int32_t dy = subtract_wrapping(now.y, last.y);
    m.dy.compress(xy_, m.y_median[median].median(), dy, single + size_context(m.dx.last_class(), 20));
    m.y_median[median].add(dy);

    const std::uint32_t level = return_level(n, r);
    const std::uint32_t k = (m.dx.last_class() + m.dy.last_class()) / 2;
    m.z.compress(z_, m.z_by_level[level], now.z, single + size_context(k, 18));
    m.z_by_level[level] = now.z;

    trace.channel = static_cast<std::uint8_t>(channel);
    trace.item_context = static_cast<std::uint8_t>(item_context);
    trace.changed = static_cast<std::uint8_t>((changed >> kChangedShift) & 7u);
    trace.return_kind = static_cast<std::uint8_t>((r == 1 ? 2u : 0u) | (r >= n ? 1u : 0u));

    last = now;
    last.gps_time_changed = time_changed;
}

[[gnu::flatten]] void ReturnsXyzEncoder::encode(PointTrace* trace, std::size_t count, const std::uint8_t* item,
                                                std::size_t stride) {
    for (std::size_t i = 0; i < count; ++i, item += stride) encode_point(item, trace[i]);
}

// ---- the other layers ------------------------------------------------------------------

void add_point14_encoders(const ItemEncodeSetup& setup, std::vector<std::unique_ptr<LayerEncoder>>& out) {
    constexpr ContextRule rule = ContextRule::kPoint14;
    out.push_back(make_layer_encoder(setup, ClassificationEncoder{}, rule));
    out.push_back(make_layer_encoder(setup, FlagsEncoder{}, rule));
    out.push_back(make_layer_encoder(setup, IntensityEncoder{}, rule));
    out.push_back(make_layer_encoder(setup, ScanAngleEncoder{}, rule));
    out.push_back(make_layer_encoder(setup, UserDataEncoder{}, rule));
    out.push_back(make_layer_encoder(setup, PointSourceEncoder{}, rule));
    out.push_back(make_gps_time14_encoder(setup));
}

}  // namespace lidarscout::laz::detail::point14
