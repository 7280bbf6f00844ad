// The state that the POINT10 v2 decoder and encoder keep across a chunk, defined once for
// both so they start every chunk alike and predict from the same values: the last point,
// running medians of the X/Y deltas and the last intensity and Z per return context, the
// models, and the reset at chunk start. The integer coders are IntegerDecompressor in the
// decoder and IntegerCompressor in the encoder.
#pragma once

#include <array>
#include <cstdint>

#include "laz/arithmetic_models.hpp"
#include "laz/point10/item_common.hpp"
#include "laz/point10/point10_record.hpp"
#include "laz/point10/symbols_v2.hpp"

namespace lidarscout::laz::point10 {

// Median of the last five values, updated in the LAZ way: the window is a sorted list of
// five, and each new value evicts the largest or the smallest, alternating whenever the
// new value lands on the side being evicted from.
class RunningMedian5 {
public:
    void reset() {
        sorted_ = {};
        evict_largest_ = true;
    }
    std::int32_t median() const { return sorted_[2]; }

    void add(std::int32_t v) {
        if (evict_largest_) {
            const bool upper = v >= sorted_[2];
            int i = 4;
            for (; i > 0 && v < sorted_[i - 1]; --i) sorted_[i] = sorted_[i - 1];
            sorted_[i] = v;
            if (upper) evict_largest_ = false;
        } else {
            const bool lower = v <= sorted_[2];
            int i = 0;
            for (; i < 4 && sorted_[i + 1] < v; ++i) sorted_[i] = sorted_[i + 1];
            sorted_[i] = v;
            if (lower) evict_largest_ = true;
        }
    }

private:
    std::array<std::int32_t, 5> sorted_{};
    bool evict_largest_ = true;
};

// Context tables indexed [number of returns][return number]: a return "kind" (16 values,
// for intensity and XY medians) and a return "level" (8 values, for Z). Out-of-spec
// combinations get contexts of their own. Defined in point10_v2.cpp.
extern const std::uint8_t kReturnKind[8][8];
extern const std::uint8_t kReturnLevel[8][8];

// The decoder and the encoder derive from this; `IntegerCoder` is IntegerDecompressor or
// IntegerCompressor.
template <class IntegerCoder>
class Point10StateV2 {
protected:
    // Starts a chunk whose first (raw) POINT10 item is `first`: the last point is `first`,
    // everything else is back in its start state. Out of line (point10_v2_state.cpp), as it
    // runs once a chunk, away from the point loops.
    void init(const std::uint8_t* first);

    Point10Record last_;
    std::array<RunningMedian5, 16> x_median_;
    std::array<RunningMedian5, 16> y_median_;
    std::array<std::uint16_t, 16> last_intensity_{};
    std::array<std::int32_t, 8> last_z_{};

    SymbolModel changed_mask_{point10_v2::kChangeMaskSymbols};
    ByteModelsByPrevious return_flags_models_;
    ByteModelsByPrevious classification_models_;
    ByteModelsByPrevious user_data_models_;
    std::array<SymbolModel, 2> scan_angle_models_{SymbolModel(256), SymbolModel(256)};
    IntegerCoder intensity_{16, 4};
    IntegerCoder point_source_{16, 1};
    IntegerCoder dx_{32, 2};
    IntegerCoder dy_{32, 22};
    IntegerCoder z_{32, 20};

private:
    void reset_predictions();
    void reset_models();
};

}  // namespace lidarscout::laz::point10
