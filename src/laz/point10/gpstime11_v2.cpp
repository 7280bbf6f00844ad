// GPSTIME11 v2: the symbol alphabets and the sequence logic.
#include "laz/point10/gpstime11_v2.hpp"

#include "core/error.hpp"
#include "laz/point10/symbols_v2.hpp"

namespace lidarscout::laz::point10 {

using namespace gpstime11_v2;  // the symbols and contexts

namespace {

// Sequence switches per point that a valid stream can contain (one); more means corruption.
constexpr int kMaxSwitches = 4;

}  // namespace

GpsTime11DecoderV2::GpsTime11DecoderV2() = default;

void GpsTime11DecoderV2::start_new_sequence(ArithmeticDecoder& dec) {
    const auto upper = static_cast<std::uint32_t>(
        delta_coder_.decompress(dec, static_cast<std::int32_t>(time_[current_] >> 32), kCtxUpperHalf));
    const std::uint32_t lower = dec.read_int();
    open_sequence((std::uint64_t{upper} << 32) | lower);
}

[[gnu::flatten]] void GpsTime11DecoderV2::decode_time(ArithmeticDecoder& dec) {
    for (int switches = 0; switches <= kMaxSwitches; ++switches) {
        const std::int32_t last_delta = delta_[current_];
        if (last_delta == 0) {
            const std::uint32_t s = dec.decode_symbol(after_zero_model_);
            if (s == kAfterZeroDelta) {
                delta_[current_] = delta_coder_.decompress(dec, 0, kCtxFirstDelta);
                time_[current_] += static_cast<std::uint64_t>(std::int64_t{delta_[current_]});
                extreme_count_[current_] = 0;
            } else if (s == kAfterZeroFull) {
                start_new_sequence(dec);
            } else if (s >= kAfterZeroSwitch) {
                current_ = (current_ + s - kAfterZeroSwitch + 1) & 3;
                continue;
            }
            return;
        }

        const std::uint32_t s = dec.decode_symbol(multiple_model_);
        if (s == kFull) {
            start_new_sequence(dec);
            return;
        }
        if (s > kFull) {
            current_ = (current_ + s - kFull) & 3;
            continue;
        }
        if (s == kUnchanged) return;

        std::int32_t delta;
        const auto m = static_cast<std::int32_t>(s);
        if (m == 1) {
            delta = delta_coder_.decompress(dec, last_delta, kCtxSameDelta);
            extreme_count_[current_] = 0;
        } else if (m == 0) {
            delta = delta_coder_.decompress(dec, 0, kCtxLarge);
            count_extreme(delta);
        } else if (m < kMaxMultiple) {
            delta = delta_coder_.decompress(dec, mul_wrapping(m, last_delta),
                                            m < 10 ? kCtxSmallMultiple : kCtxMultiple);
        } else if (m == kMaxMultiple) {
            delta = delta_coder_.decompress(dec, mul_wrapping(kMaxMultiple, last_delta), kCtxMaxMultiple);
            count_extreme(delta);
        } else {
            const std::int32_t negative = kMaxMultiple - m;  // -1 .. kMinMultiple
            if (negative > kMinMultiple) {
                delta = delta_coder_.decompress(dec, mul_wrapping(negative, last_delta), kCtxNegativeMultiple);
            } else {
                delta = delta_coder_.decompress(dec, mul_wrapping(kMinMultiple, last_delta), kCtxMinMultiple);
                count_extreme(delta);
            }
        }
        time_[current_] += static_cast<std::uint64_t>(std::int64_t{delta});
        return;
    }
    throw Error("GPS time: too many sequence switches in one point (corrupt chunk)");
}

}  // namespace lidarscout::laz::point10
