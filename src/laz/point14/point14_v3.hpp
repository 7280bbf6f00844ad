// Decoder of the POINT14 item of layered chunks (LAS 1.4 formats 6-10; item versions 3 and
// 4, which decode POINT14 alike and differ only in the context they hand on to the other
// items, see PointTrace). Its nine layers, in stream order: returns/XY (scanner channel,
// return number and count, X, Y; it drives the contexts of everything else) and Z, both
// always decoded, then classification, flags, intensity, scan angle, user data, point
// source ID and GPS time (see gps_time14_v3.hpp).
#pragma once

#include <array>
#include <cstdint>
#include <memory>
#include <vector>

#include "laz/integer_decompressor.hpp"
#include "laz/point10/point10_v2.hpp"
#include "laz/point14/layer_common.hpp"

namespace lidarscout::laz::point14 {

inline constexpr std::size_t kPoint14Size = 30;
inline constexpr std::size_t kPoint14Layers = 9;

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
    struct Value {
        std::int32_t x = 0;
        std::int32_t y = 0;
        std::int32_t z = 0;
        std::uint32_t return_number = 0;
        std::uint32_t returns = 0;  // number of returns of the pulse
        bool gps_time_changed = false;
    };
    struct Models {
        std::array<SymbolModel, 8> changed = symbol_models<8>(128);  // by the last point's return kind
        SymbolModel channel_step{3};
        LazySymbolModels<16, 16> returns;        // by the last number of returns
        LazySymbolModels<16, 16> return_number;  // by the last return number (time changed)
        SymbolModel return_step{13};             // return number jump when the time did not change
        IntegerDecompressor dx{32, 2};
        IntegerDecompressor dy{32, 22};
        IntegerDecompressor z{32, 20};
        std::array<point10::RunningMedian5, 12> x_median;
        std::array<point10::RunningMedian5, 12> y_median;
        std::array<std::int32_t, 8> z_by_level{};  // last Z per return level

        void begin(Value& v) {
            v.gps_time_changed = false;
            z_by_level.fill(v.z);
        }
    };

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

}  // namespace lidarscout::laz::point14
