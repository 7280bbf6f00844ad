// Decoder of the WAVEPACKET13 item, version 1 (LAS formats 4 and 5 in point-wise LAZ):
// descriptor index, waveform data offset (same, right after the last packet, a coded
// delta, or raw), packet size, return point location and the XYZ(t) direction, each
// predicted from the last point's value.
#pragma once

#include <array>
#include <cstdint>

#include "laz/arithmetic_decoder.hpp"
#include "laz/integer_decompressor.hpp"
#include "laz/items/item_common.hpp"

namespace lidarscout::laz::detail::point10 {

class Wavepacket13DecoderV1 {
public:
    static constexpr std::size_t kSize = 29;

    Wavepacket13DecoderV1();

    // Starts a chunk whose first (raw) packet is at `first`.
    void init(const std::uint8_t* first);

    void decode(ArithmeticDecoder& dec, std::uint8_t* out);

private:
    // The item after its descriptor byte; the floats are predicted as their bit patterns.
    struct Packet {
        std::uint64_t offset = 0;
        std::uint32_t size = 0;
        std::int32_t return_point = 0;
        std::array<std::int32_t, 3> xyz{};
    };
    static Packet load_packet(const std::uint8_t* p);
    static void store_packet(const Packet& packet, std::uint8_t* p);

    Packet last_;
    std::int32_t last_offset_delta_ = 0;
    std::uint32_t last_offset_kind_ = 0;

    SymbolModel descriptor_model_{256};
    std::array<SymbolModel, 4> offset_kind_models_{SymbolModel(4), SymbolModel(4), SymbolModel(4), SymbolModel(4)};
    IntegerDecompressor offset_delta_{32, 1};
    IntegerDecompressor size_{32, 1};
    IntegerDecompressor return_point_{32, 1};
    IntegerDecompressor xyz_{32, 3};
};

}  // namespace lidarscout::laz::detail::point10
