// POINT14 version 3 encoding: the returns/XY/Z pass and the codecs of classification, flags,
// intensity, scan angle, user data and point source ID (GPS time has its own file).
#include "laz/point14/point14_v3_encoder.hpp"


#include "laz/point14/gps_time14_v3_encoder.hpp"
#include "laz/point14/symbols_v3.hpp"

namespace lidarscout::laz::point14 {
namespace {

namespace f = point14_field;

std::int32_t subtract_wrapping(std::int32_t a, std::int32_t b) {
    return static_cast<std::int32_t>(static_cast<std::uint32_t>(a) - static_cast<std::uint32_t>(b));
}

// ---- codecs of the layers after returns/XY/Z ---------------------------------------------

// Each codec takes its Value, Models and read() from the state it shares with the decoder
// (point14_v3_state.hpp) and adds how a value is coded.

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
    std::uint32_t changed = (channel != last_channel ? kChannelChanged : 0u) |
                            ((now.point_source != last.point_source ? std::uint32_t{PointTrace::kPointSourceChanged} : 0u)
                             << kChangedShift) |
                            ((time_changed ? std::uint32_t{PointTrace::kGpsTimeChanged} : 0u) << kChangedShift) |
                            ((now.scan_angle != last.scan_angle ? std::uint32_t{PointTrace::kScanAngleChanged} : 0u)
                             << kChangedShift) |
                            (now.returns != last.returns ? kReturnsChanged : 0u);
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

}  // namespace lidarscout::laz::point14
