// The state that the GPSTIME11 v2 decoder and encoder keep across a chunk, defined once
// for both: the four time sequences (last time, reference delta, run of extreme multiples),
// the current and newest sequence, the models, the reset at chunk start and the sequence
// bookkeeping both sides do alike.
#pragma once

#include <array>
#include <cstdint>

#include "laz/arithmetic_models.hpp"
#include "laz/point10/item_common.hpp"
#include "laz/point10/symbols_v2.hpp"

namespace lidarscout::laz::point10 {

// The decoder and the encoder derive from this; `IntegerCoder` is IntegerDecompressor or
// IntegerCompressor.
template <class IntegerCoder>
class GpsTime11StateV2 {
protected:
    // Starts a chunk whose first (raw) time is at `first`: sequence 0 holds it, everything
    // else is back in its start state. Out of line (gpstime11_v2_state.cpp), as it runs once
    // a chunk, away from the point loops.
    void init(const std::uint8_t* first);

    // Makes the next sequence slot, starting at `time`, the current sequence.
    void open_sequence(std::uint64_t time) {
        newest_ = (newest_ + 1) & 3;
        current_ = newest_;
        time_[current_] = time;
        delta_[current_] = 0;
        extreme_count_[current_] = 0;
    }

    // Takes `delta` as the sequence's new reference delta after several extreme multiples.
    void count_extreme(std::int32_t delta) {
        if (++extreme_count_[current_] > gpstime11_v2::kMaxExtremeCount) {
            delta_[current_] = delta;
            extreme_count_[current_] = 0;
        }
    }

    std::array<std::uint64_t, 4> time_{};  // bit patterns of the doubles
    std::array<std::int32_t, 4> delta_{};
    std::array<std::int32_t, 4> extreme_count_{};
    std::uint32_t current_ = 0;
    std::uint32_t newest_ = 0;

    SymbolModel multiple_model_{gpstime11_v2::kMultipleSymbols};
    SymbolModel after_zero_model_{gpstime11_v2::kAfterZeroSymbols};
    IntegerCoder delta_coder_{32, gpstime11_v2::kDeltaContexts};
};

}  // namespace lidarscout::laz::point10
