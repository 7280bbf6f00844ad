// POINT10 v2 state: the return-kind context tables and the reset at chunk start, shared by the
// decoder's and the encoder's integer coders (neither defines anything the other uses).
#include "laz/point10/point10_v2_state.hpp"

#include "laz/integer_compressor.hpp"
#include "laz/integer_decompressor.hpp"

namespace lidarscout::laz::point10 {

// Well-formed pairs (1 <= r <= n <= 5) are numbered 0..14 for the kind and by n - r for
// the level; the rest of each table spreads the odd pairs over the remaining contexts.
const std::uint8_t kReturnKind[8][8] = {
    {15, 14, 13, 12, 11, 10, 9, 8},  {14, 0, 1, 3, 6, 10, 10, 9},    {13, 1, 2, 4, 7, 11, 11, 10},
    {12, 3, 4, 5, 8, 12, 12, 11},    {11, 6, 7, 8, 9, 13, 13, 12},   {10, 10, 11, 12, 13, 14, 14, 13},
    {9, 10, 11, 12, 13, 14, 15, 14}, {8, 9, 10, 11, 12, 13, 14, 15},
};

const std::uint8_t kReturnLevel[8][8] = {
    {0, 1, 2, 3, 4, 5, 6, 7}, {1, 0, 1, 2, 3, 4, 5, 6}, {2, 1, 0, 1, 2, 3, 4, 5}, {3, 2, 1, 0, 1, 2, 3, 4},
    {4, 3, 2, 1, 0, 1, 2, 3}, {5, 4, 3, 2, 1, 0, 1, 2}, {6, 5, 4, 3, 2, 1, 0, 1}, {7, 6, 5, 4, 3, 2, 1, 0},
};

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
