// The GPSTIME11 item, version 2: the out-of-line parts of its state, decoder
// and encoder (see gpstime11_v2.hpp).
#include "laz/items/point10/gpstime11_v2.hpp"

#include <limits>

#include "core/error.hpp"
#include "laz/integer_compressor.hpp"
#include "laz/integer_decompressor.hpp"

namespace lidarscout::laz::detail::point10 {

// ---- State shared by the decoder and the encoder
// GPSTIME11 v2 state: the reset at chunk start, for the decoder's and the encoder's integer
// coders.
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

// ---- Decoder
// GPSTIME11 v2: the symbol alphabets and the sequence logic.
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

        const std::uint32_t s = dec.decode_likely_symbol(multiple_model_);
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

// ---- Encoder
// GPSTIME11 v2 encoder: the choice of symbol for each time and the sequence logic.
using namespace gpstime11_v2;  // the symbols and contexts

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

}  // namespace lidarscout::laz::detail::point10
