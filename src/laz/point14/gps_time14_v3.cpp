// GPS time layer of POINT14: the sequence bookkeeping and the delta coding.
#include "laz/point14/gps_time14_v3.hpp"

#include "core/error.hpp"
#include "laz/integer_decompressor.hpp"
#include "laz/point14/gps_time14_v3_state.hpp"
#include "laz/point14/symbols_v3.hpp"

namespace lidarscout::laz::point14 {
namespace {

// A valid stream switches sequence at most once per point; a corrupt one could keep going.
constexpr int kMaxSwitchesPerPoint = 16;

// Value, Models (with the sequences) and read() come from the state shared with the encoder.
struct GpsTimeCodec : GpsTime14State<IntegerDecompressor> {
    void write(std::uint8_t* item, Value v) const { store(item + point14_field::kGpsTime, v); }

    void decode(ArithmeticDecoder& dec, Models& m, Value& v, const PointTrace& t) const {
        if (!t.gps_time_changed()) return;
        advance(dec, m);
        v = m.time[m.current];
    }

private:
    static void add_delta(Models& m, std::int32_t delta) {
        m.time[m.current] += static_cast<std::uint64_t>(static_cast<std::int64_t>(delta));
    }

    // A time coded in full starts the next sequence slot: the upper half predicted from the
    // current time's, the lower half raw.
    static void open_sequence(ArithmeticDecoder& dec, Models& m) {
        const auto upper_prediction = static_cast<std::int32_t>(m.time[m.current] >> 32);
        const auto upper = static_cast<std::uint32_t>(m.delta.decompress(dec, upper_prediction, kUpperHalf));
        const std::uint32_t lower = dec.read_int();
        m.open_sequence((std::uint64_t{upper} << 32) | lower);
    }

    // The delta for a multiple symbol below kNewSequence (other than 1).
    static std::int32_t multiple_delta(ArithmeticDecoder& dec, Models& m, std::uint32_t symbol) {
        const std::int32_t reference = m.reference[m.current];
        std::int32_t delta;
        if (symbol == 0) {
            delta = m.delta.decompress(dec, 0, kOwnDelta);
            m.note_extreme(delta);
        } else if (symbol < std::uint32_t{kLargestMultiple}) {
            const auto multiple = static_cast<std::int32_t>(symbol);
            const DeltaContext context = symbol < 10 ? kSmallMultiple : kLargeMultiple;
            delta = m.delta.decompress(dec, mul_wrapping(multiple, reference), context);
        } else if (symbol == std::uint32_t{kLargestMultiple}) {
            delta = m.delta.decompress(dec, mul_wrapping(kLargestMultiple, reference), kLargestMult);
            m.note_extreme(delta);
        } else {
            const std::int32_t multiple = kLargestMultiple - static_cast<std::int32_t>(symbol);
            if (multiple > kSmallestMultiple) {
                delta = m.delta.decompress(dec, mul_wrapping(multiple, reference), kNegativeMultiple);
            } else {
                delta = m.delta.decompress(dec, mul_wrapping(kSmallestMultiple, reference), kSmallestMult);
                m.note_extreme(delta);
            }
        }
        return delta;
    }

    // Moves the current sequence to the point's time (switching sequences as coded).
    static void advance(ArithmeticDecoder& dec, Models& m) {
        for (int switches = 0; switches <= kMaxSwitchesPerPoint; ++switches) {
            const std::uint32_t s = m.current;
            if (m.reference[s] == 0) {
                const std::uint32_t symbol = dec.decode_symbol(m.after_zero);
                if (symbol == 0) {
                    m.reference[s] = m.delta.decompress(dec, 0, kAfterZero);
                    add_delta(m, m.reference[s]);
                    m.extreme_run[s] = 0;
                    return;
                }
                if (symbol == 1) return open_sequence(dec, m);
                m.current = (s + symbol - 1) & 3u;
                continue;
            }
            const std::uint32_t symbol = dec.decode_symbol(m.multiple);
            if (symbol == 1) {
                add_delta(m, m.delta.decompress(dec, m.reference[s], kSameDelta));
                m.extreme_run[s] = 0;
                return;
            }
            if (symbol < kNewSequence) return add_delta(m, multiple_delta(dec, m, symbol));
            if (symbol == kNewSequence) return open_sequence(dec, m);
            m.current = (s + symbol - kNewSequence) & 3u;
        }
        throw Error("too many sequence switches for one point (corrupt data)");
    }
};

}  // namespace

PlacedLayer make_gps_time14_layer(std::span<const std::uint8_t> stream, const ItemSetup& setup) {
    return make_layer(stream, setup, GpsTimeCodec{}, ContextRule::kPoint14, "GPS time");
}

}  // namespace lidarscout::laz::point14
