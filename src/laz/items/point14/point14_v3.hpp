// The POINT14 item of layered chunks, versions 3 and 4 (LAS 1.4 formats 6-10): one file set
// (point14_v3.hpp/.cpp) holds all of this item version, nothing of it lives elsewhere: its symbols,
// the state its decoder and encoder share, the decoder and the encoder.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <vector>

#include "laz/arithmetic_models.hpp"
#include "laz/integer_compressor.hpp"
#include "laz/integer_decompressor.hpp"
#include "laz/items/point10/point10_v2.hpp"
#include "laz/items/point14/layer_common.hpp"
#include "laz/items/point14/layer_encoder.hpp"

namespace lidarscout::laz::detail::point14 {

// ---- Symbols and contexts (the decoder and the encoder agree on them by construction)
// ---- POINT14 returns/XY layer -------------------------------------------------------------

// Bits of the change symbol (128 symbols) that opens every point.
inline constexpr std::uint32_t kReturnStepMask = 3u;  // 0 same, 1 +1, 2 -1, 3 coded
inline constexpr std::uint32_t kReturnsChanged = 1u << 2;
inline constexpr std::uint32_t kChangedShift = 3;  // bits 3-5: scan angle, GPS time, point source (PointTrace order)
inline constexpr std::uint32_t kChannelChanged = 1u << 6;

// Context of the X/Y medians for [number of returns][return number]: six classes that
// separate single, first, last and intermediate returns (out-of-spec pairs included).
inline constexpr std::uint8_t kReturnClass[16][16] = {
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

// ---- State shared by the decoder and the encoder
// What the POINT14 layer decoders and encoders (below)
// share, defined once so both sides start every chunk and every scanner channel alike: the
// record layout, and for each layer the value it predicts from, how that value is read from
// a raw record (the chunk's first point), and the models a channel context owns (with
// begin(), their start from the context's first value). The integer coders are
// IntegerDecompressor in the decoders and IntegerCompressor in the encoders.
inline constexpr std::size_t kPoint14Size = 30;

// Byte offsets of the fields in a POINT14 record.
namespace point14_field {
inline constexpr std::size_t kX = 0;
inline constexpr std::size_t kY = 4;
inline constexpr std::size_t kZ = 8;
inline constexpr std::size_t kIntensity = 12;
inline constexpr std::size_t kReturns = 14;  // return number (low 4 bits), number of returns
inline constexpr std::size_t kFlags = 15;    // classification flags (0-3), channel (4-5), scan direction, edge
inline constexpr std::size_t kClassification = 16;
inline constexpr std::size_t kUserData = 17;
inline constexpr std::size_t kScanAngle = 18;
inline constexpr std::size_t kPointSource = 20;
inline constexpr std::size_t kGpsTime = 22;
}  // namespace point14_field

// Scanner channel of a raw POINT14 record.
inline std::uint32_t point14_channel(const std::uint8_t* item) { return (item[point14_field::kFlags] >> 4) & 3u; }

// ---- the returns/XY and Z layers -------------------------------------------------------------

// The last point of a channel as the returns/XY and Z layers predict from it.
struct ReturnsXyzValue {
    std::int32_t x = 0;
    std::int32_t y = 0;
    std::int32_t z = 0;
    std::uint32_t return_number = 0;
    std::uint32_t returns = 0;  // number of returns of the pulse
    bool gps_time_changed = false;

    static ReturnsXyzValue read(const std::uint8_t* item) {
        const std::uint8_t returns = item[point14_field::kReturns];
        ReturnsXyzValue v;
        v.x = load<std::int32_t>(item + point14_field::kX);
        v.y = load<std::int32_t>(item + point14_field::kY);
        v.z = load<std::int32_t>(item + point14_field::kZ);
        v.return_number = returns & 0x0Fu;
        v.returns = returns >> 4;
        return v;
    }
};

template <class IntegerCoder>
struct ReturnsXyzModels {
    std::array<SymbolModel, 8> changed = symbol_models<8>(128);  // by the last point's return kind
    SymbolModel channel_step{3};
    LazySymbolModels<16, 16> returns;        // by the last number of returns
    LazySymbolModels<16, 16> return_number;  // by the last return number (time changed)
    SymbolModel return_step{13};             // return number jump when the time did not change
    IntegerCoder dx{32, 2};
    IntegerCoder dy{32, 22};
    IntegerCoder z{32, 20};
    std::array<RunningMedian5, 12> x_median;
    std::array<RunningMedian5, 12> y_median;
    std::array<std::int32_t, 8> z_by_level{};  // last Z per return level

    void begin(ReturnsXyzValue& v) {
        v.gps_time_changed = false;
        z_by_level.fill(v.z);
    }
};

// ---- the other layers ------------------------------------------------------------------------
// Each provides Value, Models and read(item), as ContextLayer (layer_common.hpp) and
// ContextLayerEncoder (layer_encoder.hpp) expect; the codecs derive from these.

struct ClassificationState {
    using Value = std::uint8_t;
    struct Models {
        LazySymbolModels<64, 256> by_last;  // by the last class (5 bits) and "single return"
        void begin(Value&) {}
    };
    Value read(const std::uint8_t* item) const { return item[point14_field::kClassification]; }
};

// Six flag bits as the layer codes them: classification flags (bits 0-3), scan direction
// (bit 4), edge of flight line (bit 5). In the record the last two sit at bits 6 and 7,
// around the channel bits that the returns/XY layer codes.
struct FlagsState {
    using Value = std::uint8_t;
    struct Models {
        LazySymbolModels<64, 64> by_last;
        void begin(Value&) {}
    };
    Value read(const std::uint8_t* item) const {
        const std::uint8_t b = item[point14_field::kFlags];
        return static_cast<Value>((b & 0x0Fu) | ((b >> 2) & 0x30u));
    }
};

template <class IntegerCoder>
struct IntensityState {
    using Value = std::uint16_t;
    struct Models {
        IntegerCoder intensity{16, 4};
        std::array<std::uint16_t, 8> by_kind{};  // last intensity per return kind and time change
        void begin(Value& v) { by_kind.fill(v); }
    };
    Value read(const std::uint8_t* item) const { return load<std::uint16_t>(item + point14_field::kIntensity); }
};

struct UserDataState {
    using Value = std::uint8_t;
    struct Models {
        LazySymbolModels<64, 256> by_last;  // by the last value / 4
        void begin(Value&) {}
    };
    Value read(const std::uint8_t* item) const { return item[point14_field::kUserData]; }
};

// A 16-bit field coded against its last value by one integer coder: the scan angle (two
// contexts: whether the GPS time changed) and the point source ID.
template <class IntegerCoder, class V, std::size_t Offset, std::uint32_t Contexts>
struct Field16State {
    using Value = V;
    struct Models {
        IntegerCoder coder{16, Contexts};
        void begin(Value&) {}
    };
    Value read(const std::uint8_t* item) const { return load<Value>(item + Offset); }
};

template <class IntegerCoder>
using ScanAngleState = Field16State<IntegerCoder, std::int16_t, point14_field::kScanAngle, 2>;
template <class IntegerCoder>
using PointSourceState = Field16State<IntegerCoder, std::uint16_t, point14_field::kPointSource, 1>;

// ---- Decoder
// Decoder of the POINT14 item of layered chunks (LAS 1.4 formats 6-10; item versions 3 and
// 4, which decode POINT14 alike and differ only in the context they hand on to the other
// items, see PointTrace). Its nine layers, in stream order: returns/XY (scanner channel,
// return number and count, X, Y; it drives the contexts of everything else) and Z, both
// always decoded, then classification, flags, intensity, scan angle, user data, point
// source ID and GPS time (see gps_time14_v3.hpp).
inline constexpr std::size_t kPoint14Layers = 9;

// The returns/XY layer together with the Z layer (both are always decoded): which
// attributes changed, the scanner channel, the return number and count, the X/Y deltas
// (predicted by running medians) and Z (predicted by the last Z of the same return level).
// Records per point what the other layers need.
class ReturnsXyzLayer {
public:
    // `write_returns`: whether the caller wants the returns byte and the channel bits.
    ReturnsXyzLayer(const ItemSetup& setup, bool write_returns);

    void write_first(std::uint8_t* item);
    // Decodes the next `count` points, filling trace[0 .. count).
    void decode(PointTrace* trace, std::size_t count, std::uint8_t* item, std::size_t stride);

    // Bytes taken from / made up past the end of the two streams; layers entropy-decoded.
    std::size_t bytes_consumed() const {
        return xy_decoder_.bytes_consumed() + (z_coded_ ? z_decoder_.bytes_consumed() : 0);
    }
    std::size_t overrun() const { return xy_decoder_.overrun() + (z_coded_ ? z_decoder_.overrun() : 0); }
    std::uint32_t layers_decoded() const { return z_coded_ ? 2 : 1; }

private:
    // The state of a channel context, shared with the encoder (above).
    using Value = ReturnsXyzValue;
    using Models = ReturnsXyzModels<IntegerDecompressor>;

    // The steps of one point: return number and count, X and Y, Z (each updates `last`).
    static void decode_returns(ArithmeticDecoder& dec, Models& m, Value& last, std::uint32_t changed,
                               bool time_changed);
    static void decode_xy(ArithmeticDecoder& dec, Models& m, Value& last, bool time_changed);
    static void decode_z(ArithmeticDecoder& dec, Models& m, Value& last);
    void store(std::uint8_t* item, const Value& v, std::uint32_t channel) const;

    ArithmeticDecoder xy_decoder_;
    ArithmeticDecoder z_decoder_;
    ChannelContexts<Models, Value> contexts_;
    bool z_coded_;          // false: Z never changes in the chunk (empty layer)
    bool write_returns_;
    bool hand_on_channel_;  // version 4: the other items always get the channel as context
};

// The returns/XY/Z pass (always decoded: XYZ are always wanted).
std::unique_ptr<ReturnsXyzLayer> make_returns_xyz_layer(const ItemSetup& setup);

// Adds the passes of the other seven layers that the caller's fields need.
void add_point14_layers(const ItemSetup& setup, std::vector<PlacedLayer>& out);

// ---- Encoder
// Encoder of the POINT14 item of layered chunks, version 3 (the mirror of the decoder above):
// the returns/XY and Z layers in one pass that also leaves the PointTrace of every point,
// then one pass per layer for classification, flags, intensity, scan angle, user data,
// point source ID and GPS time (see gps_time14_v3.hpp).

// The returns/XY and Z layers: which attributes changed (against the last point of the same
// scanner channel), the channel, the return number and count, X/Y against running medians
// and Z against the last Z of the same return level.
class ReturnsXyzEncoder {
public:
    explicit ReturnsXyzEncoder(const ItemEncodeSetup& setup);
    ReturnsXyzEncoder(const ReturnsXyzEncoder&) = delete;
    ReturnsXyzEncoder& operator=(const ReturnsXyzEncoder&) = delete;

    // Codes the next `count` points, filling trace[0 .. count).
    void encode(PointTrace* trace, std::size_t count, const std::uint8_t* item, std::size_t stride);

    // Ends both streams; both are always stored.
    void finish();
    std::span<const std::uint8_t> xy_bytes() const { return xy_bytes_; }
    std::span<const std::uint8_t> z_bytes() const { return z_bytes_; }

private:
    // The last point of a channel, as far as this pass compares or predicts it: what the
    // decoder predicts from (the state shared with it, above) and the fields
    // whose changes this pass codes.
    struct Value : ReturnsXyzValue {
        double gps_time = 0;  // compared as a double, as LASzip does
        std::int16_t scan_angle = 0;
        std::uint16_t point_source = 0;
    };
    using Models = ReturnsXyzModels<IntegerCompressor>;

    static Value read(const std::uint8_t* item);
    void encode_point(const std::uint8_t* item, PointTrace& trace);

    std::vector<std::uint8_t> xy_bytes_;
    std::vector<std::uint8_t> z_bytes_;
    ArithmeticEncoder xy_;
    ArithmeticEncoder z_;
    ChannelContexts<Models, Value> contexts_;
};

// Adds the encoders of the seven layers after returns/XY and Z, in stream order.
void add_point14_encoders(const ItemEncodeSetup& setup, std::vector<std::unique_ptr<LayerEncoder>>& out);

}  // namespace lidarscout::laz::detail::point14
