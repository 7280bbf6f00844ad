// The LASzip arithmetic (range) decoder over one in-memory byte stream: one LAZ chunk
// (compressor 2) or one layer of a chunk (compressor 3). Decodes bits and symbols with the
// adaptive models of arithmetic_models.hpp, and raw bit fields of up to 64 bits.
//
// Bounds: the decoder never reads outside its span. Reads past the end yield zero bytes,
// which is exactly what a LASzip writer appends when it closes a stream, so a valid stream
// decodes the same whether or not those trailing zeros are present; overrun() tells how many
// bytes were made up, so a caller can reject a truncated chunk. Raw reads whose value cannot
// come from a valid stream throw lidarscout::Error (without a file: callers add it).
#pragma once

#include <algorithm>
#include <cstdint>
#include <cstring>
#include <span>

#include "laz/arithmetic_models.hpp"
#include "laz/decode_trace.hpp"

namespace lidarscout::laz {

class ArithmeticDecoder {
public:
    ArithmeticDecoder() = default;
    explicit ArithmeticDecoder(std::span<const std::uint8_t> stream) { start(stream); }

    // Begins decoding `stream`: the first four bytes prime the code value. The span must
    // outlive the decoding.
    void start(std::span<const std::uint8_t> stream) {
        data_ = stream.data();
        size_ = stream.size();
        pos_ = 0;
        length_ = kMaxLength;
        value_ = 0;
        for (int i = 0; i < 4; ++i) value_ = (value_ << 8) | next_byte();
#ifdef LIDARSCOUT_LAZ_TRACE
        if (decode_trace_sink) decode_trace_sink->on_start(stream);
#endif
    }

    // Bytes taken from the stream so far (including made-up ones past the end).
    std::size_t bytes_consumed() const { return pos_; }
    // How many bytes past the end of the stream had to be made up (0 for a valid stream).
    std::size_t overrun() const { return pos_ > size_ ? pos_ - size_ : 0; }

    // One bit under an adaptive binary model.
    std::uint32_t decode_bit(BitModel& m) {
        const std::uint32_t split = m.zero_probability() * (length_ >> kBitProbabilityBits);
        const std::uint32_t bit = value_ >= split;
        take_bit(m, bit, split);
        return bit;
    }

    // One symbol under an adaptive symbol model.
    std::uint32_t decode_symbol(SymbolModel& m) {
        const std::uint32_t full = length_;
        length_ >>= kSymbolProbabilityBits;
        return traced(m, search_symbol(m, full), false);
    }

    // The same, for models whose most frequent symbol usually comes (a scanner's pattern of
    // changed fields, GPS time's step kinds, colour change masks): that symbol's interval is
    // tested first (SymbolModel::guess), which takes the search (a division and two dependent
    // table reads, or a count over 16 entries) off the chain of dependent steps from one symbol to
    // the next. Other models are better off without the test: it costs instructions at every
    // symbol and a misprediction at every miss (tried on every model: no faster on any tile).
    std::uint32_t decode_likely_symbol(SymbolModel& m) {
        const std::uint32_t full = length_;
        length_ >>= kSymbolProbabilityBits;
        const SymbolModel::Guess guess = m.guess();  // a copy: taking the symbol may re-estimate the model
        const std::uint32_t low = guess.low * length_;
        const std::uint32_t high = guess.last ? full : guess.high * length_;
        if (value_ - low < high - low) {  // in the guess's interval (never when it is empty)
            take_interval(m, guess.symbol, low, high);
            return traced(m, guess.symbol, true);
        }
        return traced(m, search_symbol(m, full), true);
    }

    // ---- For bench_replay's floor: a value known in advance taken as the decode calls above take
    // what they find (interval, renormalisation, model adaptation), without finding it. Only
    // the value the stream holds keeps the decoder in step.
    void take_known_symbol(SymbolModel& m, std::uint32_t symbol) {
        const std::uint32_t full = length_;
        length_ >>= kSymbolProbabilityBits;
        take_symbol(m, symbol, full);
    }
    void take_known_bit(BitModel& m, std::uint32_t bit) {
        take_bit(m, bit, m.zero_probability() * (length_ >> kBitProbabilityBits));
    }
    void take_known_raw(std::uint32_t bits, std::uint32_t v) {
        length_ >>= bits;
        value_ -= length_ * v;
        renormalize();
    }

    // Raw (equiprobable) fields.
    std::uint32_t read_bit() { return read_raw(1); }
    // 1 to 32 bits.
    std::uint32_t read_bits(std::uint32_t bits) {
        if (bits > 19) {  // in two steps, low 16 bits first, to keep the precision
            const std::uint32_t low = read_raw(16);
            return (read_bits(bits - 16) << 16) | low;
        }
        return read_raw(bits);
    }
    std::uint8_t read_byte() { return static_cast<std::uint8_t>(read_raw(8)); }
    std::uint16_t read_short() { return static_cast<std::uint16_t>(read_raw(16)); }
    std::uint32_t read_int() {
        const std::uint32_t low = read_short();
        return (std::uint32_t{read_short()} << 16) | low;
    }
    std::uint64_t read_int64() {
        const std::uint64_t low = read_int();
        return (std::uint64_t{read_int()} << 32) | low;
    }

private:
    static constexpr std::uint32_t kMinLength = 0x01000000u;  // renormalise below 2^24
    static constexpr std::uint32_t kMaxLength = 0xFFFFFFFFu;

    std::uint32_t next_byte() {
        const std::uint32_t b = pos_ < size_ ? data_[pos_] : 0u;
        ++pos_;
        return b;
    }

    // The symbol whose interval holds the code value (`full`: the length before the >> 15 scaling,
    // already applied to length_), then taken.
    std::uint32_t search_symbol(SymbolModel& m, std::uint32_t full) {
        std::uint32_t symbol;
        if (m.has_lookup()) {
            const std::uint32_t scaled = value_ / length_;
            // The clamps only matter for corrupt streams (a code value beyond the interval): the
            // slot stays in the table, and the scan stops at the sentinel past the last symbol.
            const std::uint32_t slot = std::min(scaled >> m.lookup_shift(), m.lookup_size());
            const std::uint32_t bound = std::min(scaled, SymbolModel::kSentinel - 1);
            symbol = m.lookup()[slot];  // the first candidate; rarely more than one or two
            while (m.cdf(symbol + 1) <= bound) ++symbol;
        } else {
            symbol = m.last_at_or_below(value_, length_);  // no division for small alphabets
        }
        take_symbol(m, symbol, full);
        return symbol;
    }

    // The interval of `symbol` (`full`: the length before the >> 15 scaling), then renormalise
    // and adapt the model.
    void take_symbol(SymbolModel& m, std::uint32_t symbol, std::uint32_t full) {
        const std::uint32_t low = m.cdf(symbol) * length_;  // scaled ends of the symbol's interval
        const std::uint32_t above = m.cdf(symbol + 1) * length_;  // (the sentinel past the last symbol)
        const std::uint32_t high = symbol == m.last_symbol() ? full : above;  // the whole length for the last
        take_interval(m, symbol, low, high);
    }
    // The interval [low, high) of `symbol`, scaled: taken, renormalised, the model adapted.
    void take_interval(SymbolModel& m, std::uint32_t symbol, std::uint32_t low, std::uint32_t high) {
        value_ -= low;
        length_ = high - low;
        renormalize();
        m.record(symbol);
    }

    // Reports a decoded symbol to the trace sink (in a trace build; `likely`: decoded by
    // decode_likely_symbol) and returns it.
    std::uint32_t traced([[maybe_unused]] SymbolModel& m, std::uint32_t symbol, [[maybe_unused]] bool likely) {
#ifdef LIDARSCOUT_LAZ_TRACE
        if (decode_trace_sink) decode_trace_sink->on_symbol({data_, size_}, m, symbol, likely);
#endif
        return symbol;
    }

    // The side of `split` that `bit` names, then renormalise and adapt the model.
    void take_bit(BitModel& m, std::uint32_t bit, std::uint32_t split) {
        if (bit == 0) {
            length_ = split;
        } else {
            value_ -= split;
            length_ -= split;
        }
        if (length_ < kMinLength) renormalize();
        m.record(bit);
#ifdef LIDARSCOUT_LAZ_TRACE
        if (decode_trace_sink) decode_trace_sink->on_bit({data_, size_}, m, bit);
#endif
    }

    // Shifts in the whole bytes that bring length_ back to at least 2^24 (none when it is):
    // without a branch on whether a decode crossed a byte boundary, which is unpredictable
    // (mispredictions fall by a fifth on point10 and point14 tiles under callgrind's branch
    // model). length_ is never 0: from a length of at least 2^24, a symbol keeps at least
    // length >> 15, a 0 bit split > value >= 0, a 1 bit at least length >> 13 and a raw read
    // length >> 19; so at most 3 bytes, and the clz (undefined for 0) is defined.
    void renormalize() {
        const auto bytes = static_cast<std::uint32_t>(__builtin_clz(length_)) >> 3;
        if (pos_ + 4 > size_) [[unlikely]] {  // near the end: byte by byte, zeros past it
            for (std::uint32_t i = 0; i < bytes; ++i) value_ = (value_ << 8) | next_byte();
        } else {
            std::uint32_t next;  // the next four stream bytes, big-endian
            std::memcpy(&next, data_ + pos_, 4);
            next = __builtin_bswap32(next);
            const std::uint64_t joined = (std::uint64_t{value_} << 32) | next;
            value_ = static_cast<std::uint32_t>((joined << (8 * bytes)) >> 32);
            pos_ += bytes;
        }
        length_ <<= 8 * bytes;
    }

    // `bits` (1..19) equiprobable bits in one step.
    std::uint32_t read_raw(std::uint32_t bits) {
        length_ >>= bits;
        const std::uint32_t v = value_ / length_;
        value_ -= length_ * v;
        renormalize();
        if (v >> bits) [[unlikely]] fail_corrupt(bits);
#ifdef LIDARSCOUT_LAZ_TRACE
        if (decode_trace_sink) decode_trace_sink->on_raw({data_, size_}, bits, v);
#endif
        return v;
    }

    [[noreturn]] static void fail_corrupt(std::uint32_t bits);

    const std::uint8_t* data_ = nullptr;
    std::size_t size_ = 0;
    std::size_t pos_ = 0;
    std::uint32_t value_ = 0;
    std::uint32_t length_ = kMaxLength;
};

}  // namespace lidarscout::laz
