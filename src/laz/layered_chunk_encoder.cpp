// Layered chunk encoding: checks the item list, builds one encoder per layer, runs the
// returns/XY/Z pass and then every other layer's pass block by block (the other layers'
// contexts depend on what the first pass learnt), then assembles the chunk.
#include "laz/layered_chunk_encoder.hpp"

#include <algorithm>
#include <array>
#include <cstring>
#include <memory>
#include <string>

#include "core/error.hpp"
#include "laz/items/point14/byte14_v3.hpp"
#include "laz/items/point14/point14_v3.hpp"
#include "laz/items/point14/rgb14_v3.hpp"
#include "laz/items/point14/rgbnir14_v3.hpp"
#include "laz/items/point14/wavepacket14_v3.hpp"

namespace lidarscout::laz {
namespace {

using las::ItemType;
using detail::point14::LayerEncoder;

// Points per block: a block's records and traces stay in cache while every layer's pass
// runs over them.
constexpr std::size_t kBlockPoints = 1024;

[[noreturn]] void fail_items(const las::LaszipVlr& laz) {
    std::string list;
    for (const las::LazItem& item : laz.items) {
        if (!list.empty()) list += ", ";
        list += std::string(las::item_type_name(item.type)) + " v" + std::to_string(item.version) + " (" +
                std::to_string(item.size) + " bytes)";
    }
    throw Error("LAZ encoder: unsupported item list [" + list +
                "] for compressor 3 (POINT14 v3, then optionally RGB14 or RGBNIR14 v3, WAVEPACKET14 v3 and "
                "BYTE14 v3)");
}

// Accepts POINT14, then RGB14 or RGBNIR14, then WAVEPACKET14, then BYTE14, all version 3 and of the right
// size.
void check_items(const las::LaszipVlr& laz) {
    if (laz.compressor != 3) throw Error("layered encoder called for LAZ compressor " + std::to_string(laz.compressor));
    if (laz.coder != 0) throw Error("LAZ encoder: unsupported coder " + std::to_string(laz.coder));
    std::size_t i = 0;
    const auto next_is = [&](ItemType type, std::size_t size) {
        if (i >= laz.items.size() || static_cast<ItemType>(laz.items[i].type) != type) return false;
        const las::LazItem& item = laz.items[i];
        if (item.version != 3 || (size != 0 ? item.size != size : item.size == 0)) fail_items(laz);
        ++i;
        return true;
    };
    if (!next_is(ItemType::Point14, detail::point14::kPoint14Size)) fail_items(laz);
    if (!next_is(ItemType::Rgb14, detail::point14::kRgb14Size)) {
        next_is(ItemType::RgbNir14, detail::point14::kRgbNir14Size);
    }
    next_is(ItemType::Wavepacket14, detail::point14::kWavepacket14Size);
    next_is(ItemType::Byte14, 0);
    if (i != laz.items.size()) fail_items(laz);
}

void put_u32(std::vector<std::uint8_t>& out, std::size_t at, std::uint32_t v) { std::memcpy(out.data() + at, &v, 4); }

}  // namespace

void encode_layered_chunk(const las::LaszipVlr& laz, std::span<const std::uint8_t> records, std::uint64_t point_count,
                          std::vector<std::uint8_t>& out) {
    check_items(laz);
    const std::size_t record = laz.record_length();
    if (point_count == 0) throw Error("LAZ encoder: a chunk needs at least one point");
    if (point_count > records.size() / record || records.size() != point_count * record) {
        throw Error("LAZ encoder: " + std::to_string(records.size()) + " bytes are not " + std::to_string(point_count) +
                    " records of " + std::to_string(record) + " bytes");
    }
    if (point_count > UINT32_MAX) throw Error("LAZ encoder: more than 2^32 - 1 points in one chunk");

    // One encoder per layer, in stream order (returns/XY and Z are held apart).
    const std::uint8_t* first = records.data();
    const detail::point14::ItemEncodeSetup point_setup{first, detail::point14::point14_channel(first)};
    detail::point14::ReturnsXyzEncoder returns_xyz(point_setup);
    std::vector<std::unique_ptr<LayerEncoder>> layers;
    std::vector<std::size_t> layer_offsets;  // the item's offset in the record, per layer
    std::size_t offset = 0;
    for (const las::LazItem& item : laz.items) {
        const detail::point14::ItemEncodeSetup setup{first + offset, point_setup.first_channel};
        switch (static_cast<ItemType>(item.type)) {
            case ItemType::Point14: detail::point14::add_point14_encoders(setup, layers); break;
            case ItemType::Rgb14: detail::point14::add_rgb14_encoders(setup, layers); break;
            case ItemType::RgbNir14: detail::point14::add_rgbnir14_encoders(setup, layers); break;
            case ItemType::Wavepacket14: detail::point14::add_wavepacket14_encoders(setup, layers); break;
            default: detail::point14::add_byte14_encoders(setup, item.size, layers); break;
        }
        layer_offsets.resize(layers.size(), offset);
        offset += item.size;
    }

    std::array<detail::point14::PointTrace, kBlockPoints> trace;
    for (std::uint64_t start = 1; start < point_count; start += kBlockPoints) {
        const auto count = static_cast<std::size_t>(std::min<std::uint64_t>(kBlockPoints, point_count - start));
        const std::uint8_t* block = first + start * record;
        returns_xyz.encode(trace.data(), count, block, record);
        for (std::size_t l = 0; l < layers.size(); ++l) {
            layers[l]->encode(trace.data(), count, block + layer_offsets[l], record);
        }
    }
    returns_xyz.finish();
    for (auto& layer : layers) layer->finish();

    // The raw first record, the point count, the layer sizes, the layers.
    out.insert(out.end(), first, first + record);
    const std::size_t sizes_at = out.size();
    const std::size_t layer_count = 2 + layers.size();
    out.resize(sizes_at + 4 * (1 + layer_count));
    put_u32(out, sizes_at, static_cast<std::uint32_t>(point_count));
    put_u32(out, sizes_at + 4, static_cast<std::uint32_t>(returns_xyz.xy_bytes().size()));
    put_u32(out, sizes_at + 8, static_cast<std::uint32_t>(returns_xyz.z_bytes().size()));
    for (std::size_t l = 0; l < layers.size(); ++l) {
        put_u32(out, sizes_at + 12 + 4 * l, static_cast<std::uint32_t>(layers[l]->stored().size()));
    }
    const auto append = [&](std::span<const std::uint8_t> bytes) { out.insert(out.end(), bytes.begin(), bytes.end()); };
    append(returns_xyz.xy_bytes());
    append(returns_xyz.z_bytes());
    for (const auto& layer : layers) append(layer->stored());
}

}  // namespace lidarscout::laz
