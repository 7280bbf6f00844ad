// POINT10 v2 state: the reset at chunk start, for the decoder's and the encoder's integer
// coders.
#include "laz/point10/point10_v2_state.hpp"

#include "laz/integer_compressor.hpp"
#include "laz/integer_decompressor.hpp"

namespace lidarscout::laz::point10 {

template <class IntegerCoder>
void Point10StateV2<IntegerCoder>::init(const std::uint8_t* first) {
    reset_predictions();
    reset_models();
    last_ = Point10Record::load(first);
}

template <class IntegerCoder>
void Point10StateV2<IntegerCoder>::reset_predictions() {
    for (auto& m : x_median_) m.reset();
    for (auto& m : y_median_) m.reset();
    last_intensity_.fill(0);
    last_z_.fill(0);
}

template <class IntegerCoder>
void Point10StateV2<IntegerCoder>::reset_models() {
    changed_mask_.reset();
    return_flags_models_.reset();
    classification_models_.reset();
    user_data_models_.reset();
    for (auto& m : scan_angle_models_) m.reset();
    intensity_.reset();
    point_source_.reset();
    dx_.reset();
    dy_.reset();
    z_.reset();
}

template class Point10StateV2<IntegerDecompressor>;
template class Point10StateV2<IntegerCompressor>;

}  // namespace lidarscout::laz::point10
