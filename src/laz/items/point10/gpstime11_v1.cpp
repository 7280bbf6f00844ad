// GPSTIME11 v1: the symbol alphabets and the prediction of the next delta.
#include "laz/items/point10/gpstime11_v1.hpp"

namespace lidarscout::laz::detail::point10 {
namespace {

// Multiple model: symbols below kRawTime are multiples of the last delta (0 stands for
// a quarter of it), kRawTime means a raw 64-bit time, the last symbol "unchanged".
constexpr std::uint32_t kMultipleSymbols = 512;
constexpr std::uint32_t kRawTime = kMultipleSymbols - 2;
constexpr std::uint32_t kExtremeMultiple = kMultipleSymbols - 3;

// Model used after a zero delta: 0 unchanged, 1 a 32-bit delta, 2 a raw 64-bit time.
constexpr std::uint32_t kAfterZeroDelta = 1;
constexpr std::uint32_t kAfterZeroRaw = 2;

// Contexts of the delta coder.
constexpr std::uint32_t kCtxFirstDelta = 0;
constexpr std::uint32_t kCtxSameDelta = 1;
constexpr std::uint32_t kCtxQuarter = 2;
constexpr std::uint32_t kCtxSmallMultiple = 3;
constexpr std::uint32_t kCtxMultiple = 4;
constexpr std::uint32_t kCtxLargeMultiple = 5;

}  // namespace

GpsTime11DecoderV1::GpsTime11DecoderV1() : multiple_model_(kMultipleSymbols) {}

void GpsTime11DecoderV1::init(const std::uint8_t* first) {
    time_ = load<std::uint64_t>(first);
    delta_ = 0;
    extreme_count_ = 0;
    multiple_model_.reset();
    after_zero_model_.reset();
    delta_coder_.reset();
}

void GpsTime11DecoderV1::decode_time(ArithmeticDecoder& dec) {
    if (delta_ == 0) {
        const std::uint32_t s = dec.decode_symbol(after_zero_model_);
        if (s == kAfterZeroDelta) {
            delta_ = delta_coder_.decompress(dec, 0, kCtxFirstDelta);
            time_ += static_cast<std::uint64_t>(std::int64_t{delta_});
        } else if (s == kAfterZeroRaw) {
            time_ = dec.read_int64();
        }
        return;
    }

    const std::uint32_t s = dec.decode_symbol(multiple_model_);
    if (s == kRawTime) {
        time_ = dec.read_int64();
        return;
    }
    if (s > kRawTime) return;  // unchanged

    std::int32_t delta;
    const auto m = static_cast<std::int32_t>(s);
    if (m == 1) {
        delta = delta_coder_.decompress(dec, delta_, kCtxSameDelta);
        delta_ = delta;
        extreme_count_ = 0;
    } else if (m == 0) {
        delta = delta_coder_.decompress(dec, delta_ / 4, kCtxQuarter);
        if (++extreme_count_ > 3) {
            delta_ = delta;
            extreme_count_ = 0;
        }
    } else {
        const std::uint32_t ctx = m < 10 ? kCtxSmallMultiple : (m < 50 ? kCtxMultiple : kCtxLargeMultiple);
        delta = delta_coder_.decompress(dec, mul_wrapping(m, delta_), ctx);
        if (s == kExtremeMultiple && ++extreme_count_ > 3) {
            delta_ = delta;
            extreme_count_ = 0;
        }
    }
    time_ += static_cast<std::uint64_t>(std::int64_t{delta});
}

}  // namespace lidarscout::laz::detail::point10
