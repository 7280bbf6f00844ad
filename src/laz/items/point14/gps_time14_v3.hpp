// The GPS time layer of the POINT14 item, versions 3 and 4 (layered chunks): one file set
// (gps_time14_v3.hpp/.cpp) holds all of this item version, nothing of it lives elsewhere: its
// symbols, the state its decoder and encoder share, the decoder and the encoder.
#pragma once

#include <array>
#include <cstdint>
#include <memory>
#include <span>

#include "laz/arithmetic_models.hpp"
#include "laz/items/point14/layer_common.hpp"
#include "laz/items/point14/layer_encoder.hpp"
#include "laz/items/point14/point14_v3.hpp"

namespace lidarscout::laz::detail::point14 {

// ---- Symbols and contexts (the decoder and the encoder agree on them by construction)
// ---- POINT14 GPS time layer ----------------------------------------------------------------

// Symbols of the "multiple" model: 0 (a delta coded on its own), 1 .. 500 (that multiple
// of the reference delta), 501 .. 510 (multiples -1 .. -10), 511 (a new sequence), 512 .. 514
// (switch to the sequence 1 .. 3 places further).
inline constexpr std::int32_t kLargestMultiple = 500;
inline constexpr std::int32_t kSmallestMultiple = -10;
inline constexpr std::uint32_t kNewSequence = kLargestMultiple - kSmallestMultiple + 1;  // 511
inline constexpr std::uint32_t kMultipleSymbols = kNewSequence + 4;
// After a zero delta a smaller model: 0 (a coded delta), 1 (new sequence), 2 .. 4 (switch).
inline constexpr std::uint32_t kAfterZeroSymbols = 5;
// Extreme multiples in a row after which the coded delta becomes the reference.
inline constexpr std::int32_t kExtremeRunLimit = 3;

// Integer-coder contexts of the delta coder.
enum DeltaContext : std::uint32_t {
    kAfterZero = 0, kSameDelta = 1, kSmallMultiple = 2, kLargeMultiple = 3, kLargestMult = 4,
    kNegativeMultiple = 5, kSmallestMult = 6, kOwnDelta = 7, kUpperHalf = 8,
};

// ---- State shared by the decoder and the encoder
// What the decoder and the encoder (gps_time14_v3.cpp) of the
// POINT14 GPS time layer share, defined once: the value, how it is read from a raw record,
// and the models and sequences of a channel context with their start and the bookkeeping
// both sides do alike. The integer coder is IntegerDecompressor in the decoder and
// IntegerCompressor in the encoder.

// The codecs derive from this (see ContextLayer and ContextLayerEncoder).
template <class IntegerCoder>
struct GpsTime14State {
    using Value = std::uint64_t;  // bit pattern of the double
    struct Models {
        SymbolModel multiple{kMultipleSymbols};
        SymbolModel after_zero{kAfterZeroSymbols};
        IntegerCoder delta{32, 9};
        std::array<std::uint64_t, 4> time{};
        std::array<std::int32_t, 4> reference{};  // reference delta per sequence
        std::array<std::int32_t, 4> extreme_run{};
        std::uint32_t current = 0;
        std::uint32_t newest = 0;

        void begin(Value& v) { time[0] = v; }

        // Makes the next sequence slot, starting at `t`, the current sequence.
        void open_sequence(std::uint64_t t) {
            newest = (newest + 1) & 3u;
            current = newest;
            time[current] = t;
            reference[current] = 0;
            extreme_run[current] = 0;
        }

        // Counts an extreme multiple; a run of them makes `delta` the new reference.
        void note_extreme(std::int32_t delta) {
            if (++extreme_run[current] > kExtremeRunLimit) {
                reference[current] = delta;
                extreme_run[current] = 0;
            }
        }
    };

    Value read(const std::uint8_t* item) const { return load<std::uint64_t>(item + point14_field::kGpsTime); }
};

// ---- Decoder
// The GPS time layer of POINT14 (item versions 3 and 4). Times are coded as the bit
// patterns of the doubles, in up to four interleaved sequences per scanner channel (e.g.
// pulses from several mirrors): each keeps its last time and a reference 32-bit delta. A
// symbol says whether the next time is that delta times a small multiple (plus a coded
// correction), a switch to another sequence, or a new sequence whose time is coded in full.

// The GPS time layer's pass (constant if the layer is empty in the chunk).
PlacedLayer make_gps_time14_layer(std::span<const std::uint8_t> stream, const ItemSetup& setup);

// ---- Encoder
// Encoder of the GPS time layer of POINT14 (version 3), the mirror of the decoder above: for
// every time that changed it picks the symbol LASzip's writer picks (a multiple of the
// sequence's reference delta plus a correction, a switch to another of the channel's four
// sequences, or a new sequence coded in full).
std::unique_ptr<LayerEncoder> make_gps_time14_encoder(const ItemEncodeSetup& setup);

}  // namespace lidarscout::laz::detail::point14
