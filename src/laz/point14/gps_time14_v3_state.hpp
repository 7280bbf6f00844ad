// What the decoder (gps_time14_v3.cpp) and the encoder (gps_time14_v3_encoder.cpp) of the
// POINT14 GPS time layer share, defined once: the value, how it is read from a raw record,
// and the models and sequences of a channel context with their start and the bookkeeping
// both sides do alike. The integer coder is IntegerDecompressor in the decoder and
// IntegerCompressor in the encoder.
#pragma once

#include <array>
#include <cstdint>

#include "laz/arithmetic_models.hpp"
#include "laz/point14/layer_common.hpp"
#include "laz/point14/point14_v3_state.hpp"
#include "laz/point14/symbols_v3.hpp"

namespace lidarscout::laz::point14 {

// The codecs derive from this (see ContextLayer and ContextLayerEncoder).
template <class IntegerCoder>
struct GpsTime14State {
    using Value = std::uint64_t;  // bit pattern of the double
    struct Models {
        SymbolModel multiple{kMultipleSymbols};
        SymbolModel after_zero{kAfterZeroSymbols};
        IntegerCoder delta{32, 9};
        std::array<std::uint64_t, 4> time{};
        std::array<std::int32_t, 4> reference{};  // reference delta per sequence
        std::array<std::int32_t, 4> extreme_run{};
        std::uint32_t current = 0;
        std::uint32_t newest = 0;

        void begin(Value& v) { time[0] = v; }

        // Makes the next sequence slot, starting at `t`, the current sequence.
        void open_sequence(std::uint64_t t) {
            newest = (newest + 1) & 3u;
            current = newest;
            time[current] = t;
            reference[current] = 0;
            extreme_run[current] = 0;
        }

        // Counts an extreme multiple; a run of them makes `delta` the new reference.
        void note_extreme(std::int32_t delta) {
            if (++extreme_run[current] > kExtremeRunLimit) {
                reference[current] = delta;
                extreme_run[current] = 0;
            }
        }
    };

    Value read(const std::uint8_t* item) const { return load<std::uint64_t>(item + point14_field::kGpsTime); }
};

}  // namespace lidarscout::laz::point14
