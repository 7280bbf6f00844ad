// An observer of the arithmetic decoder for benchmarks: in a build configured with
// -DLIDARSCOUT_LAZ_TRACE=ON, every ArithmeticDecoder reports each stream it starts and each
// symbol, bit and raw field it decodes to decode_trace_sink (when one is set). bench_replay uses
// it to replay the arithmetic decoding of a file alone, without the item decoders around it.
// In other builds (the default) the decoder has no hooks and nothing here is called.
#pragma once

#include <cstdint>
#include <span>

namespace lidarscout::laz {

class SymbolModel;
class BitModel;

#ifdef LIDARSCOUT_LAZ_TRACE
inline constexpr bool kDecodeTraceBuilt = true;
#else
inline constexpr bool kDecodeTraceBuilt = false;
#endif

// What a decoder reports, each call with the stream it decodes: that tells the streams of one
// chunk (its layers) apart, also when a decoder is copied (the layer decoders work on copies).
class DecodeTraceSink {
public:
    using Stream = std::span<const std::uint8_t>;
    virtual ~DecodeTraceSink() = default;
    virtual void on_start(Stream stream) = 0;
    // `likely`: decoded by decode_likely_symbol (its guess tried first).
    virtual void on_symbol(Stream stream, SymbolModel& model, std::uint32_t symbol, bool likely) = 0;
    virtual void on_bit(Stream stream, BitModel& model, std::uint32_t bit) = 0;
    // A raw field of 1..19 bits (wider reads report their parts).
    virtual void on_raw(Stream stream, std::uint32_t bits, std::uint32_t value) = 0;
};

// The sink decoders report to (none by default). Set it only while a single thread decodes.
inline DecodeTraceSink* decode_trace_sink = nullptr;

}  // namespace lidarscout::laz
