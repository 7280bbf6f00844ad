// Point-wise chunk decoding: checks the item list, builds one decoder per item and runs
// the point loop. The usual item lists (POINT10 v2, then optionally GPSTIME11 v2, RGB12
// v2 and BYTE v2) get a loop specialised at compile time, so item calls are inlined; any
// other valid list runs a generic loop that dispatches per item.
#include "laz/pointwise_chunk.hpp"

#include <algorithm>
#include <array>
#include <cstring>
#include <string>
#include <span>
#include <tuple>
#include <type_traits>
#include <utility>
#include <variant>
#include <vector>

#include "core/error.hpp"
#include "laz/arithmetic_decoder.hpp"
#include "laz/items/point10/byte_v1.hpp"
#include "laz/items/point10/byte_v2.hpp"
#include "laz/items/point10/gpstime11_v1.hpp"
#include "laz/items/point10/gpstime11_v2.hpp"
#include "laz/items/point10/point10_v1.hpp"
#include "laz/items/point10/point10_v2.hpp"
#include "laz/items/point10/rgb12_v1.hpp"
#include "laz/items/point10/rgb12_v2.hpp"
#include "laz/items/point10/wavepacket13_v1.hpp"

namespace lidarscout::laz {
namespace {

using las::ItemType;
using las::LazItem;
using namespace detail;
using namespace detail::point10;

// Bytes a valid stream may be read past its end: none for LASzip's writers (they pad the
// stream for the decoder's look-ahead), up to the look-ahead for writers that do not.
constexpr std::size_t kMaxOverrun = 4;

ItemType type_of(const LazItem& item) { return static_cast<ItemType>(item.type); }

std::string describe(const LazItem& item) {
    return std::string(las::item_type_name(item.type)) + " version " + std::to_string(item.version) +
           " (size " + std::to_string(item.size) + ")";
}

// Size the format fixes for an item type; 0 for BYTE (any size of at least 1).
std::size_t fixed_size(ItemType type) {
    switch (type) {
        case ItemType::Point10: return kPoint10Size;
        case ItemType::GpsTime11: return GpsTime11DecoderV2::kSize;
        case ItemType::Rgb12: return Rgb12DecoderV2::kSize;
        case ItemType::Wavepacket13: return Wavepacket13DecoderV1::kSize;
        default: return 0;
    }
}

// Throws unless the item list is one this decoder handles exactly.
void check_items(const las::LaszipVlr& laz) {
    if (laz.compressor != 1 && laz.compressor != 2) {
        throw Error("point-wise decoder called for LAZ compressor " + std::to_string(laz.compressor));
    }
    if (laz.coder != 0) throw Error("unsupported LAZ coder " + std::to_string(laz.coder) + " (only 0, arithmetic)");
    if (laz.items.empty()) throw Error("LAZ item list is empty");
    for (const LazItem& item : laz.items) {
        const ItemType type = type_of(item);
        bool supported = false;
        switch (type) {
            case ItemType::Point10:
            case ItemType::GpsTime11:
            case ItemType::Rgb12:
            case ItemType::Byte: supported = item.version == 1 || item.version == 2; break;
            case ItemType::Wavepacket13: supported = item.version == 1; break;
            default: break;
        }
        if (!supported) throw Error("unsupported LAZ item for point-wise compression: " + describe(item));
        const std::size_t size = fixed_size(type);
        if (size != 0 ? item.size != size : item.size == 0) {
            throw Error("LAZ item " + describe(item) + " has the wrong size");
        }
    }
}

// Record offset of every item.
std::vector<std::size_t> item_offsets(const las::LaszipVlr& laz) {
    std::vector<std::size_t> offsets;
    std::size_t at = 0;
    for (const LazItem& item : laz.items) {
        offsets.push_back(at);
        at += item.size;
    }
    return offsets;
}

// ---- output field selection ----------------------------------------------------------

struct ByteRange {
    std::size_t offset;
    std::size_t size;
};

// Record byte ranges of the fields not asked for.
std::vector<ByteRange> unrequested_ranges(const las::LaszipVlr& laz, std::uint32_t wanted) {
    struct Field {
        std::size_t offset, size;
        std::uint32_t flag;
    };
    static constexpr Field kPoint10Fields[] = {
        {12, 2, fields::kIntensity},     {14, 1, fields::kReturns},  {15, 1, fields::kClassification},
        {16, 1, fields::kScanAngle},     {17, 1, fields::kUserData}, {18, 2, fields::kPointSource},
    };
    std::vector<ByteRange> ranges;
    std::size_t at = 0;
    for (const LazItem& item : laz.items) {
        const auto skip = [&](std::uint32_t flag, std::size_t offset, std::size_t size) {
            if (!(wanted & flag)) ranges.push_back({at + offset, size});
        };
        switch (type_of(item)) {
            case ItemType::Point10:
                for (const Field& f : kPoint10Fields) skip(f.flag, f.offset, f.size);
                break;
            case ItemType::GpsTime11: skip(fields::kGpsTime, 0, item.size); break;
            case ItemType::Rgb12: skip(fields::kRgb, 0, item.size); break;
            case ItemType::Wavepacket13: skip(fields::kWavepacket, 0, item.size); break;
            default: skip(fields::kExtraBytes, 0, item.size); break;
        }
        at += item.size;
    }
    return ranges;
}

// Zeroes the unrequested bytes of every record by AND with a per-record byte mask (a loop the
// compiler vectorises; a memset per field and record cost ~10% of an XYZ-only decode).
void clear_unrequested(const las::LaszipVlr& laz, const ChunkDecodeRequest& request, std::size_t record_length) {
    const std::vector<ByteRange> ranges = unrequested_ranges(laz, request.fields);
    if (ranges.empty()) return;
    std::vector<std::uint8_t> keep(record_length, 0xFF);
    for (const ByteRange& r : ranges) std::fill_n(keep.begin() + static_cast<std::ptrdiff_t>(r.offset), r.size, 0);
    const std::uint8_t* mask = keep.data();
    for (std::uint8_t* rec = request.out.data(); rec != request.out.data() + request.out.size(); rec += record_length) {
        for (std::size_t i = 0; i < record_length; ++i) rec[i] &= mask[i];
    }
}

// ---- the point loops -----------------------------------------------------------------

// Everything the loops need about the chunk.
struct ChunkView {
    const std::uint8_t* first;  // the raw first record
    std::span<const std::uint8_t> stream;  // the arithmetic-coded rest
    std::uint8_t* out;
    std::uint64_t point_count;
    std::size_t record_length;
};

[[noreturn]] void fail_truncated(const ChunkView& chunk, std::uint64_t point) {
    throw Error(std::string(), chunk.record_length + chunk.stream.size(),
                "LAZ chunk ends early (truncated or corrupt) at point " + std::to_string(point) + " of " +
                    std::to_string(chunk.point_count));
}

// Runs `decode_record(dec, record)` for points 1 .. point_count - 1 (point 0 is the raw
// first record, already in place).
template <class DecodeRecord>
void decode_points(const ChunkView& chunk, DecodeRecord&& decode_record) {
    if (chunk.point_count < 2) return;
    ArithmeticDecoder dec(chunk.stream);
    std::uint8_t* rec = chunk.out + chunk.record_length;
    for (std::uint64_t p = 1; p < chunk.point_count; ++p, rec += chunk.record_length) {
        decode_record(dec, rec);
        if (dec.overrun() > kMaxOverrun) [[unlikely]] fail_truncated(chunk, p);
    }
}

// One record of a fixed list of item decoders. Flattened: the arithmetic and integer
// decoding calls are inlined into the item code, which is where the time goes.
template <class... Items, std::size_t... I>
[[gnu::flatten]] void decode_fixed_record(std::tuple<Items...>& items,
                                          const std::array<std::size_t, sizeof...(Items)>& at,
                                          std::index_sequence<I...>, ArithmeticDecoder& dec, std::uint8_t* rec) {
    (std::get<I>(items).decode(dec, rec + at[I]), ...);
}

// The specialised loop for a fixed list of item decoders.
template <class... Items>
void decode_fixed(const las::LaszipVlr& laz, const ChunkView& chunk) {
    const std::vector<std::size_t> offsets = item_offsets(laz);
    constexpr auto kIndices = std::index_sequence_for<Items...>{};
    [&]<std::size_t... I>(std::index_sequence<I...>) {
        std::tuple<Items...> items{make_item<Items>(laz.items[I])...};
        const std::array<std::size_t, sizeof...(Items)> at{offsets[I]...};
        (std::get<I>(items).init(chunk.first + at[I]), ...);
        decode_points(chunk, [&](ArithmeticDecoder& dec, std::uint8_t* rec) {
            decode_fixed_record(items, at, kIndices, dec, rec);
        });
    }(kIndices);
}

// Runs decode_fixed for the usual v2 item lists; false if the list is not one of them.
bool decode_common_v2(const las::LaszipVlr& laz, const ChunkView& chunk) {
    const auto& items = laz.items;
    std::size_t i = 0;
    const auto next_is = [&](ItemType type) {
        const bool match = i < items.size() && type_of(items[i]) == type && items[i].version == 2;
        if (match) ++i;
        return match;
    };
    if (!next_is(ItemType::Point10)) return false;
    const bool gps = next_is(ItemType::GpsTime11);
    const bool rgb = next_is(ItemType::Rgb12);
    const bool bytes = next_is(ItemType::Byte);
    if (i != items.size()) return false;

    const auto run = [&]<class... Items>() {
        if (bytes) {
            decode_fixed<Items..., ByteDecoderV2>(laz, chunk);
        } else {
            decode_fixed<Items...>(laz, chunk);
        }
    };
    if (gps && rgb) {
        run.template operator()<Point10DecoderV2, GpsTime11DecoderV2, Rgb12DecoderV2>();
    } else if (gps) {
        run.template operator()<Point10DecoderV2, GpsTime11DecoderV2>();
    } else if (rgb) {
        run.template operator()<Point10DecoderV2, Rgb12DecoderV2>();
    } else {
        run.template operator()<Point10DecoderV2>();
    }
    return true;
}

using AnyItemDecoder = std::variant<Point10DecoderV1, Point10DecoderV2, GpsTime11DecoderV1, GpsTime11DecoderV2,
                                    Rgb12DecoderV1, Rgb12DecoderV2, ByteDecoderV1, ByteDecoderV2,
                                    Wavepacket13DecoderV1>;

template <class V1, class V2>
void emplace_versioned(std::vector<AnyItemDecoder>& decoders, const LazItem& item) {
    if (item.version == 1) {
        decoders.emplace_back(std::in_place_type<V1>, make_item<V1>(item));
    } else {
        decoders.emplace_back(std::in_place_type<V2>, make_item<V2>(item));
    }
}

// The loop for any checked item list.
void decode_generic(const las::LaszipVlr& laz, const ChunkView& chunk) {
    std::vector<AnyItemDecoder> decoders;
    decoders.reserve(laz.items.size());
    for (const LazItem& item : laz.items) {
        switch (type_of(item)) {
            case ItemType::Point10: emplace_versioned<Point10DecoderV1, Point10DecoderV2>(decoders, item); break;
            case ItemType::GpsTime11: emplace_versioned<GpsTime11DecoderV1, GpsTime11DecoderV2>(decoders, item); break;
            case ItemType::Rgb12: emplace_versioned<Rgb12DecoderV1, Rgb12DecoderV2>(decoders, item); break;
            case ItemType::Byte: emplace_versioned<ByteDecoderV1, ByteDecoderV2>(decoders, item); break;
            default: decoders.emplace_back(std::in_place_type<Wavepacket13DecoderV1>); break;
        }
    }
    const std::vector<std::size_t> offsets = item_offsets(laz);
    for (std::size_t i = 0; i < decoders.size(); ++i) {
        std::visit([&](auto& d) { d.init(chunk.first + offsets[i]); }, decoders[i]);
    }
    decode_points(chunk, [&](ArithmeticDecoder& dec, std::uint8_t* rec) {
        for (std::size_t i = 0; i < decoders.size(); ++i) {
            std::visit([&](auto& d) { d.decode(dec, rec + offsets[i]); }, decoders[i]);
        }
    });
}

}  // namespace

void decode_pointwise_chunk(const las::LaszipVlr& laz, const ChunkDecodeRequest& request) {
    check_items(laz);
    const std::size_t record_length = laz.record_length();
    if (request.point_count > request.out.size() / record_length ||
        request.out.size() != request.point_count * record_length) {
        throw Error("point-wise decoder: output of " + std::to_string(request.out.size()) + " bytes does not hold " +
                    std::to_string(request.point_count) + " records of " + std::to_string(record_length) + " bytes");
    }
    if (request.point_count == 0) return;
    if (request.bytes.size() < record_length) {
        throw Error(std::string(), request.bytes.size(),
                    "LAZ chunk of " + std::to_string(request.bytes.size()) +
                        " bytes is too short for its first point record of " + std::to_string(record_length));
    }

    std::memcpy(request.out.data(), request.bytes.data(), record_length);
    const ChunkView chunk{request.bytes.data(), request.bytes.subspan(record_length), request.out.data(),
                          request.point_count, record_length};
    if (!decode_common_v2(laz, chunk)) decode_generic(laz, chunk);
    clear_unrequested(laz, request, record_length);
}

}  // namespace lidarscout::laz
