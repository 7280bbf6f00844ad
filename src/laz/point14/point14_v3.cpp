// POINT14 layers: the returns/XY pass and the codecs of Z, classification, flags,
// intensity, scan angle, user data and point source ID (GPS time has its own file).
#include "laz/point14/point14_v3.hpp"

#include <cstdlib>

#include "laz/chunk_decoder.hpp"
#include "laz/point14/gps_time14_v3.hpp"

namespace lidarscout::laz::point14 {
namespace {

namespace f = point14_field;

// Bits of the returns/XY layer's change symbol.
constexpr std::uint32_t kReturnStepMask = 3u;  // 0 same, 1 +1, 2 -1, 3 coded
constexpr std::uint32_t kReturnsChanged = 1u << 2;
constexpr std::uint32_t kChangedShift = 3;      // bits 3-5: scan angle, GPS time, point source (PointTrace order)
constexpr std::uint32_t kChannelChanged = 1u << 6;

// Context of the X/Y medians for [number of returns][return number]: six classes that
// separate single, first, last and intermediate returns (out-of-spec pairs included).
constexpr std::uint8_t kReturnClass[16][16] = {
    {0, 1, 2, 3, 4, 5, 3, 4, 4, 5, 5, 5, 5, 5, 5, 5}, {1, 0, 1, 3, 3, 3, 3, 3, 3, 3, 3, 3, 3, 3, 3, 3},
    {2, 1, 2, 4, 4, 4, 4, 4, 4, 4, 4, 3, 3, 3, 3, 3}, {3, 3, 4, 5, 4, 4, 4, 4, 4, 4, 4, 4, 4, 4, 4, 4},
    {4, 3, 4, 4, 5, 4, 4, 4, 4, 4, 4, 4, 4, 4, 4, 4}, {5, 3, 4, 4, 4, 5, 4, 4, 4, 4, 4, 4, 4, 4, 4, 4},
    {3, 3, 4, 4, 4, 4, 5, 4, 4, 4, 4, 4, 4, 4, 4, 4}, {4, 3, 4, 4, 4, 4, 4, 5, 4, 4, 4, 4, 4, 4, 4, 4},
    {4, 3, 4, 4, 4, 4, 4, 4, 5, 4, 4, 4, 4, 4, 4, 4}, {5, 3, 4, 4, 4, 4, 4, 4, 4, 5, 4, 4, 4, 4, 4, 4},
    {5, 3, 4, 4, 4, 4, 4, 4, 4, 4, 5, 4, 4, 4, 4, 4}, {5, 3, 3, 4, 4, 4, 4, 4, 4, 4, 4, 5, 5, 4, 4, 4},
    {5, 3, 3, 4, 4, 4, 4, 4, 4, 4, 4, 5, 5, 5, 4, 4}, {5, 3, 3, 4, 4, 4, 4, 4, 4, 4, 4, 4, 5, 5, 5, 4},
    {5, 3, 3, 4, 4, 4, 4, 4, 4, 4, 4, 4, 4, 5, 5, 5}, {5, 3, 3, 4, 4, 4, 4, 4, 4, 4, 4, 4, 4, 4, 5, 5},
};

// Return level (Z context): how many returns separate r from n, capped at 7.
inline std::uint32_t return_level(std::uint32_t returns, std::uint32_t r) {
    const std::uint32_t gap = returns > r ? returns - r : r - returns;
    return gap < 7 ? gap : 7;
}

// Integer-coder context from a corrector size class: even classes below `cap`, else cap.
inline std::uint32_t size_context(std::uint32_t k, std::uint32_t cap) { return k < cap ? (k & ~1u) : cap; }

// ---- codecs of the layers after returns/XY ---------------------------------------------

struct ZCodec {
    using Value = std::int32_t;
    struct Models {
        IntegerDecompressor z{32, 20};
        std::array<std::int32_t, 8> by_level{};  // last Z per return level
        void begin(Value& v) { by_level.fill(v); }
    };
    Value read(const std::uint8_t* item) const { return load<std::int32_t>(item + f::kZ); }
    void write(std::uint8_t* item, Value v) const { store(item + f::kZ, v); }
    void decode(ArithmeticDecoder& dec, Models& m, Value& v, const PointTrace& t) const {
        v = m.z.decompress(dec, m.by_level[t.level], t.z_context);
        m.by_level[t.level] = v;
    }
};

struct ClassificationCodec {
    using Value = std::uint8_t;
    struct Models {
        LazySymbolModels<64, 256> by_last;  // by the last class (5 bits) and "single return"
        void begin(Value&) {}
    };
    Value read(const std::uint8_t* item) const { return item[f::kClassification]; }
    void write(std::uint8_t* item, Value v) const { item[f::kClassification] = v; }
    void decode(ArithmeticDecoder& dec, Models& m, Value& v, const PointTrace& t) const {
        const std::uint32_t slot = ((v & 0x1Fu) << 1) | (t.return_kind == 3 ? 1u : 0u);
        v = static_cast<Value>(dec.decode_symbol(m.by_last[slot]));
    }
};

// Six flag bits as the layer codes them: classification flags (bits 0-3), scan direction
// (bit 4), edge of flight line (bit 5). In the record the last two sit at bits 6 and 7,
// around the channel bits that the returns/XY layer writes.
struct FlagsCodec {
    using Value = std::uint8_t;
    struct Models {
        LazySymbolModels<64, 64> by_last;
        void begin(Value&) {}
    };
    std::uint8_t record_mask;  // record bits the caller wants from this layer

    Value read(const std::uint8_t* item) const {
        const std::uint8_t b = item[f::kFlags];
        return static_cast<Value>((b & 0x0Fu) | ((b >> 2) & 0x30u));
    }
    void write(std::uint8_t* item, Value v) const {
        const std::uint8_t bits = static_cast<std::uint8_t>((v & 0x0Fu) | ((v & 0x30u) << 2));
        item[f::kFlags] = static_cast<std::uint8_t>((item[f::kFlags] & ~record_mask) | (bits & record_mask));
    }
    void decode(ArithmeticDecoder& dec, Models& m, Value& v, const PointTrace&) const {
        v = static_cast<Value>(dec.decode_symbol(m.by_last[v]));
    }
};

struct IntensityCodec {
    using Value = std::uint16_t;
    struct Models {
        IntegerDecompressor intensity{16, 4};
        std::array<std::uint16_t, 8> by_kind{};  // last intensity per return kind and time change
        void begin(Value& v) { by_kind.fill(v); }
    };
    Value read(const std::uint8_t* item) const { return load<std::uint16_t>(item + f::kIntensity); }
    void write(std::uint8_t* item, Value v) const { store(item + f::kIntensity, v); }
    void decode(ArithmeticDecoder& dec, Models& m, Value& v, const PointTrace& t) const {
        const std::uint32_t slot = (std::uint32_t{t.return_kind} << 1) | (t.gps_time_changed() ? 1u : 0u);
        v = static_cast<Value>(m.intensity.decompress(dec, m.by_kind[slot], t.return_kind));
        m.by_kind[slot] = v;
    }
};

struct ScanAngleCodec {
    using Value = std::int16_t;
    struct Models {
        IntegerDecompressor angle{16, 2};
        void begin(Value&) {}
    };
    Value read(const std::uint8_t* item) const { return load<std::int16_t>(item + f::kScanAngle); }
    void write(std::uint8_t* item, Value v) const { store(item + f::kScanAngle, v); }
    void decode(ArithmeticDecoder& dec, Models& m, Value& v, const PointTrace& t) const {
        if (t.changed & PointTrace::kScanAngleChanged) {
            v = static_cast<Value>(m.angle.decompress(dec, v, t.gps_time_changed() ? 1u : 0u));
        }
    }
};

struct UserDataCodec {
    using Value = std::uint8_t;
    struct Models {
        LazySymbolModels<64, 256> by_last;  // by the last value / 4
        void begin(Value&) {}
    };
    Value read(const std::uint8_t* item) const { return item[f::kUserData]; }
    void write(std::uint8_t* item, Value v) const { item[f::kUserData] = v; }
    void decode(ArithmeticDecoder& dec, Models& m, Value& v, const PointTrace&) const {
        v = static_cast<Value>(dec.decode_symbol(m.by_last[v >> 2]));
    }
};

struct PointSourceCodec {
    using Value = std::uint16_t;
    struct Models {
        IntegerDecompressor source{16, 1};
        void begin(Value&) {}
    };
    Value read(const std::uint8_t* item) const { return load<std::uint16_t>(item + f::kPointSource); }
    void write(std::uint8_t* item, Value v) const { store(item + f::kPointSource, v); }
    void decode(ArithmeticDecoder& dec, Models& m, Value& v, const PointTrace& t) const {
        if (t.changed & PointTrace::kPointSourceChanged) v = static_cast<Value>(m.source.decompress(dec, v));
    }
};

}  // namespace

// ---- returns/XY ------------------------------------------------------------------------

ReturnsXyLayer::ReturnsXyLayer(std::span<const std::uint8_t> stream, const ItemSetup& setup, bool write_returns)
    : decoder_(stream), write_returns_(write_returns) {
    const std::uint8_t returns = setup.first[f::kReturns];
    Value first;
    first.x = load<std::int32_t>(setup.first + f::kX);
    first.y = load<std::int32_t>(setup.first + f::kY);
    first.return_number = returns & 0x0Fu;
    first.returns = returns >> 4;
    contexts_.start(setup.first_channel, first, true);
}

void ReturnsXyLayer::store(std::uint8_t* item, const Value& v, std::uint32_t channel) const {
    point14::store(item + f::kX, v.x);
    point14::store(item + f::kY, v.y);
    if (write_returns_) {
        item[f::kReturns] = static_cast<std::uint8_t>(v.return_number | (v.returns << 4));
        item[f::kFlags] = static_cast<std::uint8_t>(channel << 4);
    } else {
        item[f::kFlags] = 0;  // the flags layer (if wanted) fills in its bits after this pass
    }
}

void ReturnsXyLayer::write_first(std::uint8_t* item) { store(item, contexts_.value(), contexts_.channel()); }

void ReturnsXyLayer::decode(PointTrace* trace, std::size_t count, std::uint8_t* item, std::size_t stride) {
    ArithmeticDecoder dec = decoder_;  // a local copy the compiler can keep in registers
    Models* m = &contexts_.models();
    Value* last = &contexts_.value();
    for (std::size_t i = 0; i < count; ++i, item += stride) {
        const std::uint32_t last_kind = (last->return_number == 1 ? 1u : 0u) |
                                        (last->return_number >= last->returns ? 2u : 0u) |
                                        (last->gps_time_changed ? 4u : 0u);
        const std::uint32_t changed = dec.decode_symbol(m->changed[last_kind]);
        if (changed & kChannelChanged) [[unlikely]] {
            const std::uint32_t step = dec.decode_symbol(m->channel_step);
            contexts_.select((contexts_.channel() + step + 1) & 3u);
            m = &contexts_.models();
            last = &contexts_.value();
        }
        const bool time_changed = (changed & (std::uint32_t{PointTrace::kGpsTimeChanged} << kChangedShift)) != 0;

        std::uint32_t n = last->returns;
        if (changed & kReturnsChanged) n = dec.decode_symbol(m->returns[n]);
        std::uint32_t r = last->return_number;
        switch (changed & kReturnStepMask) {
            case 0: break;
            case 1: r = (r + 1) & 15u; break;
            case 2: r = (r + 15) & 15u; break;
            default:
                if (time_changed) {
                    r = dec.decode_symbol(m->return_number[r]);
                } else {
                    r = (r + dec.decode_symbol(m->return_step) + 2) & 15u;
                }
        }
        last->returns = n;
        last->return_number = r;

        const std::uint32_t single = n == 1 ? 1u : 0u;
        const std::uint32_t median = (std::uint32_t{kReturnClass[n][r]} << 1) | (time_changed ? 1u : 0u);
        const std::int32_t dx = m->dx.decompress(dec, m->x_median[median].median(), single);
        last->x = add_wrapping(last->x, dx);
        m->x_median[median].add(dx);
        const std::int32_t dy =
            m->dy.decompress(dec, m->y_median[median].median(), single + size_context(m->dx.last_class(), 20));
        last->y = add_wrapping(last->y, dy);
        m->y_median[median].add(dy);
        last->gps_time_changed = time_changed;

        PointTrace& t = trace[i];
        t.channel = static_cast<std::uint8_t>(contexts_.channel());
        t.changed = static_cast<std::uint8_t>((changed >> kChangedShift) & 7u);
        t.return_kind = static_cast<std::uint8_t>((r == 1 ? 2u : 0u) | (r >= n ? 1u : 0u));
        t.level = static_cast<std::uint8_t>(return_level(n, r));
        t.z_context = static_cast<std::uint8_t>(
            single + size_context((m->dx.last_class() + m->dy.last_class()) / 2, 18));
        store(item, *last, t.channel);
    }
    decoder_ = dec;
}

std::unique_ptr<ReturnsXyLayer> make_returns_xy_layer(const ItemSetup& setup) {
    return std::make_unique<ReturnsXyLayer>(setup.layers[0], setup, (setup.fields & fields::kReturns) != 0);
}

// ---- the other layers ------------------------------------------------------------------

void add_point14_layers(const ItemSetup& setup, std::vector<PlacedLayer>& out) {
    const auto& layers = setup.layers;
    const std::uint32_t want = setup.fields;
    out.push_back(make_layer(layers[1], setup, ZCodec{}, true, "Z"));
    if (want & fields::kClassification) {
        out.push_back(make_layer(layers[2], setup, ClassificationCodec{}, true, "classification"));
    }
    const std::uint8_t flag_bits = static_cast<std::uint8_t>((want & fields::kReturns ? 0xC0u : 0u) |
                                                             (want & fields::kClassification ? 0x0Fu : 0u));
    if (flag_bits) out.push_back(make_layer(layers[3], setup, FlagsCodec{flag_bits}, true, "flags"));
    if (want & fields::kIntensity) out.push_back(make_layer(layers[4], setup, IntensityCodec{}, true, "intensity"));
    if (want & fields::kScanAngle) out.push_back(make_layer(layers[5], setup, ScanAngleCodec{}, true, "scan angle"));
    if (want & fields::kUserData) out.push_back(make_layer(layers[6], setup, UserDataCodec{}, true, "user data"));
    if (want & fields::kPointSource) {
        out.push_back(make_layer(layers[7], setup, PointSourceCodec{}, true, "point source ID"));
    }
    if (want & fields::kGpsTime) out.push_back(make_gps_time14_layer(layers[8], setup));
}

}  // namespace lidarscout::laz::point14
