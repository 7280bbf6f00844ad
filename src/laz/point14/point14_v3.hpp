// Decoder of the POINT14 item of layered chunks (LAS 1.4 formats 6-10; item versions 3 and
// 4, which decode POINT14 alike and differ only in the context they hand on to the other
// items, see PointTrace). Its nine layers, in stream order: returns/XY (scanner channel,
// return number and count, X, Y; it drives the contexts of everything else) and Z, both
// always decoded, then classification, flags, intensity, scan angle, user data, point
// source ID and GPS time (see gps_time14_v3.hpp).
#pragma once

#include <cstdint>
#include <memory>
#include <vector>

#include "laz/integer_decompressor.hpp"
#include "laz/point14/layer_common.hpp"
#include "laz/point14/point14_v3_state.hpp"

namespace lidarscout::laz::point14 {

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
    // The state of a channel context, shared with the encoder (point14_v3_state.hpp).
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

}  // namespace lidarscout::laz::point14
