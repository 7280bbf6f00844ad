// GPSTIME11 v2 state: the reset at chunk start, for the decoder's and the encoder's integer
// coders.
#include "laz/point10/gpstime11_v2_state.hpp"

#include "laz/integer_compressor.hpp"
#include "laz/integer_decompressor.hpp"

namespace lidarscout::laz::point10 {

template <class IntegerCoder>
void GpsTime11StateV2<IntegerCoder>::init(const std::uint8_t* first) {
    time_ = {load<std::uint64_t>(first), 0, 0, 0};
    delta_.fill(0);
    extreme_count_.fill(0);
    current_ = 0;
    newest_ = 0;
    multiple_model_.reset();
    after_zero_model_.reset();
    delta_coder_.reset();
}

template class GpsTime11StateV2<IntegerDecompressor>;
template class GpsTime11StateV2<IntegerCompressor>;

}  // namespace lidarscout::laz::point10
