// Encoder of the POINT14 item of layered chunks, version 3 (the mirror of point14_v3.hpp):
// the returns/XY and Z layers in one pass that also leaves the PointTrace of every point,
// then one pass per layer for classification, flags, intensity, scan angle, user data,
// point source ID and GPS time (see gps_time14_v3_encoder.hpp).
#pragma once

#include <cstdint>
#include <memory>
#include <vector>

#include "laz/integer_compressor.hpp"
#include "laz/point14/layer_encoder.hpp"
#include "laz/point14/point14_v3_state.hpp"

namespace lidarscout::laz::point14 {

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
    // decoder predicts from (the state shared with it, point14_v3_state.hpp) and the fields
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

}  // namespace lidarscout::laz::point14
