// Point-wise chunk encoding: checks the item list, then runs a point loop specialised at
// compile time for the item combination, so the item and coder calls are inlined.
#include "laz/pointwise_chunk_encoder.hpp"

#include <array>
#include <cstring>
#include <string>
#include <tuple>
#include <type_traits>
#include <utility>

#include "core/error.hpp"
#include "laz/arithmetic_encoder.hpp"
#include "laz/items/point10/byte_v2.hpp"
#include "laz/items/point10/gpstime11_v2.hpp"
#include "laz/items/point10/point10_v2.hpp"
#include "laz/items/point10/rgb12_v2.hpp"
#include "laz/items/point10/wavepacket13_v1.hpp"

namespace lidarscout::laz {
namespace {

using las::ItemType;
using las::LazItem;
using namespace detail;
using namespace detail::point10;

// Which optional items follow POINT10.
struct ItemList {
    bool gps_time = false;
    bool rgb = false;
    bool wavepacket = false;
    bool extra_bytes = false;
};

[[noreturn]] void fail_items(const las::LaszipVlr& laz) {
    std::string list;
    for (const LazItem& item : laz.items) {
        if (!list.empty()) list += ", ";
        list += std::string(las::item_type_name(item.type)) + " v" + std::to_string(item.version) + " (" +
                std::to_string(item.size) + " bytes)";
    }
    throw Error("LAZ encoder: unsupported item list [" + list +
                "] for compressor 2 (POINT10 v2, then optionally GPSTIME11 v2, RGB12 v2, WAVEPACKET13 v1 "
                "and BYTE v2)");
}

// The list as LASzip writes it for formats 0-5, or an Error.
ItemList check_items(const las::LaszipVlr& laz) {
    if (laz.compressor != 2) {
        throw Error("point-wise encoder called for LAZ compressor " + std::to_string(laz.compressor));
    }
    if (laz.coder != 0) throw Error("LAZ encoder: unsupported coder " + std::to_string(laz.coder));
    std::size_t i = 0;
    const auto next_is = [&](ItemType type, std::size_t size, std::uint16_t version = 2) {
        if (i >= laz.items.size()) return false;
        const LazItem& item = laz.items[i];
        if (static_cast<ItemType>(item.type) != type || item.version != version) return false;
        if (size != 0 ? item.size != size : item.size == 0) fail_items(laz);
        ++i;
        return true;
    };
    if (!next_is(ItemType::Point10, kPoint10Size)) fail_items(laz);
    ItemList list;
    list.gps_time = next_is(ItemType::GpsTime11, GpsTime11EncoderV2::kSize);
    list.rgb = next_is(ItemType::Rgb12, Rgb12EncoderV2::kSize);
    list.wavepacket = next_is(ItemType::Wavepacket13, Wavepacket13EncoderV1::kSize, 1);
    list.extra_bytes = next_is(ItemType::Byte, 0);
    if (i != laz.items.size()) fail_items(laz);
    return list;
}

// One record through a fixed list of item encoders. Flattened: the arithmetic and integer
// coding calls are inlined into the item code, which is where the time goes.
template <class... Items, std::size_t... I>
[[gnu::flatten]] void encode_fixed_record(std::tuple<Items...>& items,
                                          const std::array<std::size_t, sizeof...(Items)>& at,
                                          std::index_sequence<I...>, ArithmeticEncoder& enc,
                                          const std::uint8_t* record) {
    (std::get<I>(items).encode(enc, record + at[I]), ...);
}

// Codes records 1 .. point_count - 1 (record 0 is the chunk's raw start) into `out`.
template <class... Items>
void encode_fixed(const las::LaszipVlr& laz, const std::uint8_t* records, std::uint64_t point_count,
                  std::size_t record_length, std::vector<std::uint8_t>& out) {
    constexpr auto kIndices = std::index_sequence_for<Items...>{};
    [&]<std::size_t... I>(std::index_sequence<I...>) {
        std::array<std::size_t, sizeof...(Items)> at{};
        std::size_t offset = 0;
        ((at[I] = offset, offset += laz.items[I].size), ...);
        std::tuple<Items...> items{make_item<Items>(laz.items[I])...};
        (std::get<I>(items).init(records + at[I]), ...);

        ArithmeticEncoder enc;
        enc.start(out);
        const std::uint8_t* record = records + record_length;
        for (std::uint64_t p = 1; p < point_count; ++p, record += record_length) {
            encode_fixed_record(items, at, kIndices, enc, record);
        }
        enc.done();
    }(kIndices);
}

// Picks the specialised loop for the item list.
void encode_points(const las::LaszipVlr& laz, const ItemList& list, const std::uint8_t* records,
                   std::uint64_t point_count, std::size_t record_length, std::vector<std::uint8_t>& out) {
    const auto with_bytes = [&]<class... Items>() {
        if (list.extra_bytes) {
            encode_fixed<Items..., ByteEncoderV2>(laz, records, point_count, record_length, out);
        } else {
            encode_fixed<Items...>(laz, records, point_count, record_length, out);
        }
    };
    const auto run = [&]<class... Items>() {
        if (list.wavepacket) {
            with_bytes.template operator()<Items..., Wavepacket13EncoderV1>();
        } else {
            with_bytes.template operator()<Items...>();
        }
    };
    if (list.gps_time && list.rgb) {
        run.template operator()<Point10EncoderV2, GpsTime11EncoderV2, Rgb12EncoderV2>();
    } else if (list.gps_time) {
        run.template operator()<Point10EncoderV2, GpsTime11EncoderV2>();
    } else if (list.rgb) {
        run.template operator()<Point10EncoderV2, Rgb12EncoderV2>();
    } else {
        run.template operator()<Point10EncoderV2>();
    }
}

}  // namespace

void encode_pointwise_chunk(const las::LaszipVlr& laz, std::span<const std::uint8_t> records,
                            std::uint64_t point_count, std::vector<std::uint8_t>& out) {
    const ItemList list = check_items(laz);
    const std::size_t record_length = laz.record_length();
    if (point_count == 0) throw Error("LAZ encoder: a chunk needs at least one point");
    if (point_count > records.size() / record_length || records.size() != point_count * record_length) {
        throw Error("LAZ encoder: " + std::to_string(records.size()) + " bytes are not " +
                    std::to_string(point_count) + " records of " + std::to_string(record_length) + " bytes");
    }
    out.insert(out.end(), records.begin(), records.begin() + static_cast<std::ptrdiff_t>(record_length));
    encode_points(laz, list, records.data(), point_count, record_length, out);
}

}  // namespace lidarscout::laz
