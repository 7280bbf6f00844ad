// What the POINT14 layer decoders (point14_v3.hpp) and encoders (point14_v3_encoder.hpp)
// share, defined once so both sides start every chunk and every scanner channel alike: the
// record layout, and for each layer the value it predicts from, how that value is read from
// a raw record (the chunk's first point), and the models a channel context owns (with
// begin(), their start from the context's first value). The integer coders are
// IntegerDecompressor in the decoders and IntegerCompressor in the encoders.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>

#include "laz/arithmetic_models.hpp"
#include "laz/point10/point10_v2_state.hpp"
#include "laz/point14/layer_common.hpp"

namespace lidarscout::laz::point14 {

inline constexpr std::size_t kPoint14Size = 30;

// Byte offsets of the fields in a POINT14 record.
namespace point14_field {
inline constexpr std::size_t kX = 0;
inline constexpr std::size_t kY = 4;
inline constexpr std::size_t kZ = 8;
inline constexpr std::size_t kIntensity = 12;
inline constexpr std::size_t kReturns = 14;  // return number (low 4 bits), number of returns
inline constexpr std::size_t kFlags = 15;    // classification flags (0-3), channel (4-5), scan direction, edge
inline constexpr std::size_t kClassification = 16;
inline constexpr std::size_t kUserData = 17;
inline constexpr std::size_t kScanAngle = 18;
inline constexpr std::size_t kPointSource = 20;
inline constexpr std::size_t kGpsTime = 22;
}  // namespace point14_field

// Scanner channel of a raw POINT14 record.
inline std::uint32_t point14_channel(const std::uint8_t* item) { return (item[point14_field::kFlags] >> 4) & 3u; }

// ---- the returns/XY and Z layers -------------------------------------------------------------

// The last point of a channel as the returns/XY and Z layers predict from it.
struct ReturnsXyzValue {
    std::int32_t x = 0;
    std::int32_t y = 0;
    std::int32_t z = 0;
    std::uint32_t return_number = 0;
    std::uint32_t returns = 0;  // number of returns of the pulse
    bool gps_time_changed = false;

    static ReturnsXyzValue read(const std::uint8_t* item) {
        const std::uint8_t returns = item[point14_field::kReturns];
        ReturnsXyzValue v;
        v.x = load<std::int32_t>(item + point14_field::kX);
        v.y = load<std::int32_t>(item + point14_field::kY);
        v.z = load<std::int32_t>(item + point14_field::kZ);
        v.return_number = returns & 0x0Fu;
        v.returns = returns >> 4;
        return v;
    }
};

template <class IntegerCoder>
struct ReturnsXyzModels {
    std::array<SymbolModel, 8> changed = symbol_models<8>(128);  // by the last point's return kind
    SymbolModel channel_step{3};
    LazySymbolModels<16, 16> returns;        // by the last number of returns
    LazySymbolModels<16, 16> return_number;  // by the last return number (time changed)
    SymbolModel return_step{13};             // return number jump when the time did not change
    IntegerCoder dx{32, 2};
    IntegerCoder dy{32, 22};
    IntegerCoder z{32, 20};
    std::array<point10::RunningMedian5, 12> x_median;
    std::array<point10::RunningMedian5, 12> y_median;
    std::array<std::int32_t, 8> z_by_level{};  // last Z per return level

    void begin(ReturnsXyzValue& v) {
        v.gps_time_changed = false;
        z_by_level.fill(v.z);
    }
};

// ---- the other layers ------------------------------------------------------------------------
// Each provides Value, Models and read(item), as ContextLayer (layer_common.hpp) and
// ContextLayerEncoder (layer_encoder.hpp) expect; the codecs derive from these.

struct ClassificationState {
    using Value = std::uint8_t;
    struct Models {
        LazySymbolModels<64, 256> by_last;  // by the last class (5 bits) and "single return"
        void begin(Value&) {}
    };
    Value read(const std::uint8_t* item) const { return item[point14_field::kClassification]; }
};

// Six flag bits as the layer codes them: classification flags (bits 0-3), scan direction
// (bit 4), edge of flight line (bit 5). In the record the last two sit at bits 6 and 7,
// around the channel bits that the returns/XY layer codes.
struct FlagsState {
    using Value = std::uint8_t;
    struct Models {
        LazySymbolModels<64, 64> by_last;
        void begin(Value&) {}
    };
    Value read(const std::uint8_t* item) const {
        const std::uint8_t b = item[point14_field::kFlags];
        return static_cast<Value>((b & 0x0Fu) | ((b >> 2) & 0x30u));
    }
};

template <class IntegerCoder>
struct IntensityState {
    using Value = std::uint16_t;
    struct Models {
        IntegerCoder intensity{16, 4};
        std::array<std::uint16_t, 8> by_kind{};  // last intensity per return kind and time change
        void begin(Value& v) { by_kind.fill(v); }
    };
    Value read(const std::uint8_t* item) const { return load<std::uint16_t>(item + point14_field::kIntensity); }
};

struct UserDataState {
    using Value = std::uint8_t;
    struct Models {
        LazySymbolModels<64, 256> by_last;  // by the last value / 4
        void begin(Value&) {}
    };
    Value read(const std::uint8_t* item) const { return item[point14_field::kUserData]; }
};

// A 16-bit field coded against its last value by one integer coder: the scan angle (two
// contexts: whether the GPS time changed) and the point source ID.
template <class IntegerCoder, class V, std::size_t Offset, std::uint32_t Contexts>
struct Field16State {
    using Value = V;
    struct Models {
        IntegerCoder coder{16, Contexts};
        void begin(Value&) {}
    };
    Value read(const std::uint8_t* item) const { return load<Value>(item + Offset); }
};

template <class IntegerCoder>
using ScanAngleState = Field16State<IntegerCoder, std::int16_t, point14_field::kScanAngle, 2>;
template <class IntegerCoder>
using PointSourceState = Field16State<IntegerCoder, std::uint16_t, point14_field::kPointSource, 1>;

}  // namespace lidarscout::laz::point14
