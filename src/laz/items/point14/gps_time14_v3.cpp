// The GPS time layer of the POINT14 item, versions 3 and 4: the out-of-line parts of its state, decoder
// and encoder (see gps_time14_v3.hpp).
#include "laz/items/point14/gps_time14_v3.hpp"

#include "core/error.hpp"
#include "laz/integer_compressor.hpp"
#include "laz/integer_decompressor.hpp"
#include "laz/items/point10/gpstime11_v2.hpp"

namespace lidarscout::laz::detail::point14 {

// ---- Decoder
// GPS time layer of POINT14: the sequence bookkeeping and the delta coding.
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
            const std::uint32_t symbol = dec.decode_likely_symbol(m.multiple);
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

// ---- Encoder
// GPS time layer encoding: the choice of symbol and the sequence bookkeeping.
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
            if (gps_delta_as_int32(time - m.time[(m.current + offset) & 3u])) return offset;
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
        const std::int32_t multiple = gps_delta_multiple(delta, reference);
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
            if (const auto delta = gps_delta_as_int32(time - m.time[m.current])) {
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

}  // namespace lidarscout::laz::detail::point14
