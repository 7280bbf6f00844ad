// The LASzip arithmetic (range) encoder: the exact inverse of ArithmeticDecoder. It codes bits
// and symbols under the adaptive models of arithmetic_models.hpp (updating them exactly as the
// decoder will) and raw bit fields, and appends the bytes to a caller's vector, so a chunk's
// raw first record and its coded stream can share one buffer.
//
// The interval is kept as a 32-bit base and length; whenever the length falls below 2^24 the
// top byte of the base is final and goes out. A base that overflows adds a carry into the
// bytes already written (a run of 0xFF bytes turns to zeros and the byte before grows by one).
// done() ends the stream the way LASzip does, including the two or three zero bytes a decoder
// reads ahead, so the output is byte-identical to LASzip's.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "laz/arithmetic_models.hpp"

namespace lidarscout::laz {

class ArithmeticEncoder {
public:
    ArithmeticEncoder() = default;
    ArithmeticEncoder(const ArithmeticEncoder&) = delete;
    ArithmeticEncoder& operator=(const ArithmeticEncoder&) = delete;

    // Begins a stream at the end of `out` (the bytes already there are kept). `out` must stay
    // alive and untouched by others until done().
    void start(std::vector<std::uint8_t>& out);

    // Ends the stream: writes the final bytes and the read-ahead padding, and leaves `out`
    // ending exactly with the stream. The encoder may then be started again.
    void done();

    // One bit under an adaptive binary model.
    void encode_bit(BitModel& m, std::uint32_t bit) {
        const std::uint32_t split = m.zero_probability() * (length_ >> kBitProbabilityBits);
        if (bit == 0) {
            length_ = split;
        } else {
            add_to_base(split);
            length_ -= split;
        }
        if (length_ < kMinLength) renormalize();
        m.record(bit);
    }

    // One symbol (< m.symbols()) under an adaptive symbol model.
    void encode_symbol(SymbolModel& m, std::uint32_t symbol) {
        std::uint32_t low;
        if (symbol == m.last_symbol()) {  // its interval runs to the end: no product needed
            low = m.cdf(symbol) * (length_ >> kSymbolProbabilityBits);
            length_ -= low;
        } else {
            length_ >>= kSymbolProbabilityBits;
            low = m.cdf(symbol) * length_;
            length_ = m.cdf(symbol + 1) * length_ - low;
        }
        add_to_base(low);
        if (length_ < kMinLength) renormalize();
        m.record(symbol);
    }

    // Raw (equiprobable) fields; `value` must fit in the given width.
    void write_bit(std::uint32_t bit) { write_raw(1, bit); }
    // 1 to 32 bits (more than 19 go out in two steps, the low 16 bits first).
    void write_bits(std::uint32_t bits, std::uint32_t value) {
        if (bits > 19) {
            write_raw(16, value & 0xFFFFu);
            value >>= 16;
            bits -= 16;
        }
        write_raw(bits, value);
    }
    void write_byte(std::uint8_t value) { write_raw(8, value); }
    void write_short(std::uint16_t value) { write_raw(16, value); }
    void write_int(std::uint32_t value) {
        write_short(static_cast<std::uint16_t>(value));
        write_short(static_cast<std::uint16_t>(value >> 16));
    }
    void write_int64(std::uint64_t value) {
        write_int(static_cast<std::uint32_t>(value));
        write_int(static_cast<std::uint32_t>(value >> 32));
    }

private:
    static constexpr std::uint32_t kMinLength = 0x01000000u;  // renormalise below 2^24
    static constexpr std::uint32_t kMaxLength = 0xFFFFFFFFu;
    // One renormalisation writes at most this many bytes (the length never drops below 1).
    static constexpr std::size_t kMaxBytesPerStep = 4;

    // `bits` (1..19) equiprobable bits in one step.
    void write_raw(std::uint32_t bits, std::uint32_t value) {
        length_ >>= bits;
        add_to_base(value * length_);
        if (length_ < kMinLength) renormalize();
    }

    void add_to_base(std::uint32_t x) {
        const std::uint32_t before = base_;
        base_ += x;
        if (base_ < before) [[unlikely]] propagate_carry();
    }

    // Sends out the settled top bytes of the base until the length is 2^24 or more.
    void renormalize() {
        if (static_cast<std::size_t>(end_ - next_) < kMaxBytesPerStep) [[unlikely]] grow();
        do {
            *next_++ = static_cast<std::uint8_t>(base_ >> 24);
            base_ <<= 8;
            length_ <<= 8;
        } while (length_ < kMinLength);
    }

    void propagate_carry();
    // Enlarges the output vector (keeping what is written) so that at least
    // kMaxBytesPerStep more bytes fit.
    void grow();

    std::vector<std::uint8_t>* out_ = nullptr;
    std::size_t stream_begin_ = 0;    // index in *out_ of the stream's first byte
    std::uint8_t* next_ = nullptr;    // where the next byte goes
    std::uint8_t* end_ = nullptr;     // end of the writable part of *out_
    std::uint32_t base_ = 0;
    std::uint32_t length_ = kMaxLength;
};

}  // namespace lidarscout::laz
