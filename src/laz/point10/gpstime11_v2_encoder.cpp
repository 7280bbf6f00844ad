// GPSTIME11 v2 encoder: the choice of symbol for each time and the sequence logic.
#include "laz/point10/gpstime11_v2_encoder.hpp"

#include <limits>

namespace lidarscout::laz::point10 {

using namespace gpstime11_v2;  // the symbols and contexts

std::int32_t gps_delta_multiple(std::int32_t delta, std::int32_t last_delta) {
    const float quotient = static_cast<float>(delta) / static_cast<float>(last_delta);
    const double rounded = quotient >= 0 ? double{quotient} + 0.5 : double{quotient} - 0.5;
    // Truncation toward zero keeps the value in range exactly when it lies strictly
    // between these bounds.
    if (!(rounded > -2147483649.0 && rounded < 2147483648.0)) return std::numeric_limits<std::int32_t>::min();
    return static_cast<std::int32_t>(rounded);
}

GpsTime11EncoderV2::GpsTime11EncoderV2() = default;

std::uint32_t GpsTime11EncoderV2::find_other_sequence(std::uint64_t time) const {
    for (std::uint32_t offset = 1; offset < 4; ++offset) {
        if (gps_delta_as_int32(time - time_[(current_ + offset) & 3])) return offset;
    }
    return 0;
}

void GpsTime11EncoderV2::start_new_sequence(ArithmeticEncoder& enc, std::uint64_t time) {
    delta_coder_.compress(enc, static_cast<std::int32_t>(time_[current_] >> 32), static_cast<std::int32_t>(time >> 32),
                          kCtxUpperHalf);
    enc.write_int(static_cast<std::uint32_t>(time));
    open_sequence(time);
}

[[gnu::flatten]] void GpsTime11EncoderV2::encode_time(ArithmeticEncoder& enc, std::uint64_t time) {
    // A switch lands on a sequence within 32 bits of `time`, so the loop runs at most twice.
    for (;;) {
        const bool after_zero = delta_[current_] == 0;
        SymbolModel& model = after_zero ? after_zero_model_ : multiple_model_;
        if (time == time_[current_]) {
            enc.encode_symbol(model, after_zero ? kAfterZeroUnchanged : kUnchanged);
            return;
        }
        if (const auto delta = gps_delta_as_int32(time - time_[current_])) {
            if (after_zero) {
                enc.encode_symbol(model, kAfterZeroDelta);
                delta_coder_.compress(enc, 0, *delta, kCtxFirstDelta);
                delta_[current_] = *delta;
                extreme_count_[current_] = 0;
            } else {
                encode_delta(enc, *delta);
            }
            time_[current_] = time;
            return;
        }
        if (const std::uint32_t offset = find_other_sequence(time)) {
            enc.encode_symbol(model, (after_zero ? kAfterZeroSwitch - 1 : kFull) + offset);
            current_ = (current_ + offset) & 3;
            continue;
        }
        enc.encode_symbol(model, after_zero ? kAfterZeroFull : kFull);
        start_new_sequence(enc, time);
        return;
    }
}

void GpsTime11EncoderV2::encode_delta(ArithmeticEncoder& enc, std::int32_t delta) {
    const std::int32_t last = delta_[current_];
    const std::int32_t m = gps_delta_multiple(delta, last);
    if (m == 1) {
        enc.encode_symbol(multiple_model_, 1);
        delta_coder_.compress(enc, last, delta, kCtxSameDelta);
        extreme_count_[current_] = 0;
    } else if (m > 1 && m < kMaxMultiple) {
        enc.encode_symbol(multiple_model_, static_cast<std::uint32_t>(m));
        delta_coder_.compress(enc, mul_wrapping(m, last), delta,
                              m < kSmallMultipleLimit ? kCtxSmallMultiple : kCtxMultiple);
    } else if (m >= kMaxMultiple) {
        enc.encode_symbol(multiple_model_, kMaxMultiple);
        delta_coder_.compress(enc, mul_wrapping(kMaxMultiple, last), delta, kCtxMaxMultiple);
        count_extreme(delta);
    } else if (m < 0 && m > kMinMultiple) {
        enc.encode_symbol(multiple_model_, static_cast<std::uint32_t>(kMaxMultiple - m));
        delta_coder_.compress(enc, mul_wrapping(m, last), delta, kCtxNegativeMultiple);
    } else if (m < 0) {
        enc.encode_symbol(multiple_model_, static_cast<std::uint32_t>(kMaxMultiple - kMinMultiple));
        delta_coder_.compress(enc, mul_wrapping(kMinMultiple, last), delta, kCtxMinMultiple);
        count_extreme(delta);
    } else {  // m == 0: a delta much smaller than the last one
        enc.encode_symbol(multiple_model_, 0);
        delta_coder_.compress(enc, 0, delta, kCtxLarge);
        count_extreme(delta);
    }
}

}  // namespace lidarscout::laz::point10
