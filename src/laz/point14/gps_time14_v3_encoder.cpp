// GPS time layer encoding: the choice of symbol and the sequence bookkeeping.
#include "laz/point14/gps_time14_v3_encoder.hpp"

#include "laz/integer_compressor.hpp"
#include "laz/point10/gpstime11_v2_encoder.hpp"
#include "laz/point14/gps_time14_v3_state.hpp"
#include "laz/point14/symbols_v3.hpp"

namespace lidarscout::laz::point14 {
namespace {

// Value, Models (with the sequences) and read() come from the state shared with the decoder.
struct GpsTimeEncoder : GpsTime14State<IntegerCompressor> {
    bool encode(ArithmeticEncoder& enc, Models& m, Value& last, Value now, const PointTrace& t) const {
        if (!t.gps_time_changed()) return false;
        write_time(enc, m, now);
        last = now;
        return true;
    }

private:
    // Offset (1..3) of another sequence whose last time is within 32 bits of `time`; 0 if none.
    static std::uint32_t other_sequence(const Models& m, std::uint64_t time) {
        for (std::uint32_t offset = 1; offset < 4; ++offset) {
            if (point10::gps_delta_as_int32(time - m.time[(m.current + offset) & 3u])) return offset;
        }
        return 0;
    }

    // A new sequence for `time`: the upper half predicted from the current time's, the lower
    // half raw.
    static void open_sequence(ArithmeticEncoder& enc, Models& m, std::uint64_t time) {
        m.delta.compress(enc, static_cast<std::int32_t>(m.time[m.current] >> 32), static_cast<std::int32_t>(time >> 32),
                         kUpperHalf);
        enc.write_int(static_cast<std::uint32_t>(time));
        m.open_sequence(time);
    }

    // A delta of the current sequence whose reference delta is not 0.
    static void write_multiple(ArithmeticEncoder& enc, Models& m, std::int32_t delta) {
        const std::int32_t reference = m.reference[m.current];
        const std::int32_t multiple = point10::gps_delta_multiple(delta, reference);
        if (multiple == 1) {
            enc.encode_symbol(m.multiple, 1);
            m.delta.compress(enc, reference, delta, kSameDelta);
            m.extreme_run[m.current] = 0;
        } else if (multiple > 0) {
            if (multiple < kLargestMultiple) {
                enc.encode_symbol(m.multiple, static_cast<std::uint32_t>(multiple));
                m.delta.compress(enc, mul_wrapping(multiple, reference), delta,
                                 multiple < 10 ? kSmallMultiple : kLargeMultiple);
            } else {
                enc.encode_symbol(m.multiple, static_cast<std::uint32_t>(kLargestMultiple));
                m.delta.compress(enc, mul_wrapping(kLargestMultiple, reference), delta, kLargestMult);
                m.note_extreme(delta);
            }
        } else if (multiple < 0) {
            if (multiple > kSmallestMultiple) {
                enc.encode_symbol(m.multiple, static_cast<std::uint32_t>(kLargestMultiple - multiple));
                m.delta.compress(enc, mul_wrapping(multiple, reference), delta, kNegativeMultiple);
            } else {
                enc.encode_symbol(m.multiple, static_cast<std::uint32_t>(kLargestMultiple - kSmallestMultiple));
                m.delta.compress(enc, mul_wrapping(kSmallestMultiple, reference), delta, kSmallestMult);
                m.note_extreme(delta);
            }
        } else {
            enc.encode_symbol(m.multiple, 0);
            m.delta.compress(enc, 0, delta, kOwnDelta);
            m.note_extreme(delta);
        }
    }

    // Moves the current sequence to `time` (a switch lands within 32 bits, so at most one).
    static void write_time(ArithmeticEncoder& enc, Models& m, std::uint64_t time) {
        for (;;) {
            const bool after_zero = m.reference[m.current] == 0;
            SymbolModel& model = after_zero ? m.after_zero : m.multiple;
            if (const auto delta = point10::gps_delta_as_int32(time - m.time[m.current])) {
                if (after_zero) {
                    enc.encode_symbol(model, 0);
                    m.delta.compress(enc, 0, *delta, kAfterZero);
                    m.reference[m.current] = *delta;
                    m.extreme_run[m.current] = 0;
                } else {
                    write_multiple(enc, m, *delta);
                }
                m.time[m.current] = time;
                return;
            }
            if (const std::uint32_t offset = other_sequence(m, time)) {
                enc.encode_symbol(model, (after_zero ? 1u : kNewSequence) + offset);
                m.current = (m.current + offset) & 3u;
                continue;
            }
            enc.encode_symbol(model, after_zero ? 1u : kNewSequence);
            open_sequence(enc, m, time);
            return;
        }
    }
};

}  // namespace

std::unique_ptr<LayerEncoder> make_gps_time14_encoder(const ItemEncodeSetup& setup) {
    return make_layer_encoder(setup, GpsTimeEncoder{}, ContextRule::kPoint14);
}

}  // namespace lidarscout::laz::point14
