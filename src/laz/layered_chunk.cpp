// Layered chunks: validates the item list, splits the chunk into its layer streams, builds
// one pass per wanted layer and runs the passes block by block over the points (the
// returns/XY/Z pass first, since every other layer's contexts depend on it).
#include "laz/layered_chunk.hpp"

#include <algorithm>
#include <array>
#include <cstring>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include "core/error.hpp"
#include "laz/items/point14/byte14_v3.hpp"
#include "laz/items/point14/point14_v3.hpp"
#include "laz/items/point14/rgb14_v3.hpp"
#include "laz/items/point14/rgbnir14_v3.hpp"
#include "laz/items/point14/wavepacket14_v3.hpp"

namespace lidarscout::laz {
namespace {

using las::ItemType;
using detail::point14::ItemSetup;
using detail::point14::PlacedLayer;
using detail::point14::PointTrace;

// Points per block: small enough that a block's records and traces stay in cache while
// each layer's pass runs over them.
constexpr std::size_t kBlockPoints = 1024;

[[noreturn]] void fail(std::optional<std::uint64_t> offset, const std::string& cause) {
    throw Error(std::string(), offset, "layered chunk: " + cause);
}

std::string item_text(const las::LazItem& item) {
    return std::string(las::item_type_name(item.type)) + " (size " + std::to_string(item.size) + ", version " +
           std::to_string(item.version) + ")";
}

// Size a layered item must have (0: any size of at least 1), or -1 for types that cannot
// appear in a layered chunk.
int required_size(std::uint16_t type) {
    switch (static_cast<ItemType>(type)) {
        case ItemType::Point14: return static_cast<int>(detail::point14::kPoint14Size);
        case ItemType::Rgb14: return static_cast<int>(detail::point14::kRgb14Size);
        case ItemType::RgbNir14: return static_cast<int>(detail::point14::kRgbNir14Size);
        case ItemType::Wavepacket14: return static_cast<int>(detail::point14::kWavepacket14Size);
        case ItemType::Byte14: return 0;
        default: return -1;
    }
}

// Rejects item lists we cannot decode bit-exactly: POINT14 first (and only there), then
// layered items of the right size in versions 3 or 4 (LASzip reads version 2, written by
// early tools, as 3; it has no WAVEPACKET14 version 2). Returns the record length.
std::size_t check_items(const las::LaszipVlr& laz) {
    if (laz.compressor != 3) fail(std::nullopt, "compressor " + std::to_string(laz.compressor) + " is not layered (3)");
    if (laz.coder != 0) fail(std::nullopt, "unsupported entropy coder " + std::to_string(laz.coder));
    if (laz.items.empty()) fail(std::nullopt, "the LASzip VLR lists no items");
    std::size_t record = 0;
    for (std::size_t i = 0; i < laz.items.size(); ++i) {
        const las::LazItem& item = laz.items[i];
        const int size = required_size(item.type);
        const bool is_point = item.type == static_cast<std::uint16_t>(ItemType::Point14);
        const std::uint16_t min_version = item.type == static_cast<std::uint16_t>(ItemType::Wavepacket14) ? 3 : 2;
        if (size < 0) fail(std::nullopt, "item " + item_text(item) + " cannot be decoded in a layered chunk");
        if (is_point != (i == 0)) fail(std::nullopt, "POINT14 must be the first item and only the first");
        if ((size > 0 && item.size != size) || item.size == 0) {
            fail(std::nullopt, "item " + item_text(item) + " has a wrong size");
        }
        if (item.version < min_version || item.version > 4) {
            fail(std::nullopt, "item " + item_text(item) + ": unsupported version (3 and 4 are decoded)");
        }
        record += item.size;
    }
    return record;
}

// Number of layers an item has in the chunk.
std::size_t layer_count(const las::LazItem& item) {
    switch (static_cast<ItemType>(item.type)) {
        case ItemType::Point14: return detail::point14::kPoint14Layers;
        case ItemType::RgbNir14: return 2;
        case ItemType::Byte14: return item.size;
        default: return 1;
    }
}

std::uint32_t read_u32(std::span<const std::uint8_t> bytes, std::size_t pos) {
    std::uint32_t v;
    std::memcpy(&v, bytes.data() + pos, sizeof v);
    return v;
}

// The chunk split into layer streams (in item order, then layer order).
std::vector<std::span<const std::uint8_t>> split_layers(const las::LaszipVlr& laz,
                                                        std::span<const std::uint8_t> bytes, std::size_t record) {
    std::size_t layers = 0;
    for (const auto& item : laz.items) layers += layer_count(item);
    // The raw first point, then a u32 point count (unused: the chunk table is authoritative,
    // as in LASzip), then a u32 size per layer.
    const std::size_t sizes_at = record + 4;
    if (bytes.size() < sizes_at + 4 * layers) {
        fail(bytes.size(), "chunk of " + std::to_string(bytes.size()) + " bytes ends before its layer sizes (" +
                               std::to_string(sizes_at + 4 * layers) + " bytes needed)");
    }
    std::vector<std::span<const std::uint8_t>> streams(layers);
    std::size_t pos = sizes_at + 4 * layers;
    for (std::size_t i = 0; i < layers; ++i) {
        const std::uint32_t size = read_u32(bytes, sizes_at + 4 * i);
        if (size > bytes.size() - pos) {
            fail(sizes_at + 4 * i, "layer " + std::to_string(i) + " of " + std::to_string(size) +
                                       " bytes runs past the end of the " + std::to_string(bytes.size()) +
                                       "-byte chunk");
        }
        streams[i] = bytes.subspan(pos, size);
        pos += size;
    }
    return streams;
}

// The passes of one chunk: returns/XY/Z first, then the other wanted layers.
struct ChunkPasses {
    std::unique_ptr<detail::point14::ReturnsXyzLayer> returns_xyz;
    std::vector<PlacedLayer> layers;
};

ChunkPasses build_passes(const las::LaszipVlr& laz, std::span<const std::span<const std::uint8_t>> streams,
                         const std::uint8_t* first, std::uint32_t fields) {
    ChunkPasses passes;
    const std::uint32_t channel = detail::point14::point14_channel(first);
    std::size_t offset = 0;
    std::size_t next_layer = 0;
    for (const auto& item : laz.items) {
        const std::size_t count = layer_count(item);
        const ItemSetup setup{first + offset, offset, streams.subspan(next_layer, count), fields, channel,
                              std::max<std::uint16_t>(item.version, 3)};
        switch (static_cast<ItemType>(item.type)) {
            case ItemType::Point14:
                passes.returns_xyz = detail::point14::make_returns_xyz_layer(setup);
                detail::point14::add_point14_layers(setup, passes.layers);
                break;
            case ItemType::Rgb14: detail::point14::add_rgb14_layers(setup, passes.layers); break;
            case ItemType::RgbNir14: detail::point14::add_rgbnir14_layers(setup, passes.layers); break;
            case ItemType::Wavepacket14: detail::point14::add_wavepacket14_layers(setup, passes.layers); break;
            default: detail::point14::add_byte14_layers(setup, passes.layers); break;
        }
        offset += item.size;
        next_layer += count;
    }
    return passes;
}

// Runs one layer's step, naming the layer in any error it raises.
template <class Step>
void in_layer(const char* name, Step&& step) {
    try {
        step();
    } catch (const Error& e) {
        fail(e.offset(), std::string("the ") + name + " layer: " + e.cause());
    }
}

// `zero`: clear each block's records first (bytes of unwanted fields stay zero), just before
// decoding into it, while it is in cache (a memset of the whole chunk up front costs ~4% of an
// XYZ-only decode).
void run_passes(ChunkPasses& passes, std::uint8_t* out, std::uint64_t point_count, std::size_t record, bool zero) {
    if (zero) std::memset(out, 0, record);
    passes.returns_xyz->write_first(out);
    for (auto& layer : passes.layers) layer.decoder->write_first(out + layer.item_offset);

    std::array<PointTrace, kBlockPoints> trace;
    for (std::uint64_t start = 1; start < point_count; start += kBlockPoints) {
        const auto count = static_cast<std::size_t>(std::min<std::uint64_t>(kBlockPoints, point_count - start));
        std::uint8_t* block = out + start * record;
        if (zero) std::memset(block, 0, count * record);
        in_layer("returns/XY/Z", [&] { passes.returns_xyz->decode(trace.data(), count, block, record); });
        for (auto& layer : passes.layers) {
            in_layer(layer.name,
                     [&] { layer.decoder->decode(trace.data(), count, block + layer.item_offset, record); });
        }
    }
}

// A stream that needed bytes past its end was truncated (LASzip fails on it as well).
void check_complete(const ChunkPasses& passes) {
    if (passes.returns_xyz->overrun() > 0) fail(std::nullopt, "the returns/XY or Z layer is truncated or corrupt");
    for (const auto& layer : passes.layers) {
        if (layer.decoder->overrun() > 0) {
            fail(std::nullopt, std::string("the ") + layer.name + " layer is truncated or corrupt");
        }
    }
}

LayeredChunkStats collect_stats(std::span<const std::span<const std::uint8_t>> streams, const ChunkPasses& passes) {
    LayeredChunkStats stats;
    stats.layers = static_cast<std::uint32_t>(streams.size());
    for (const auto& s : streams) stats.layer_bytes += s.size();
    stats.layers_decoded = passes.returns_xyz->layers_decoded();
    stats.bytes_consumed = passes.returns_xyz->bytes_consumed();
    for (const auto& layer : passes.layers) {
        if (layer.decoder->entropy_coded()) ++stats.layers_decoded;
        stats.bytes_consumed += layer.decoder->bytes_consumed();
    }
    return stats;
}

}  // namespace

void decode_layered_chunk(const las::LaszipVlr& laz, const ChunkDecodeRequest& request, LayeredChunkStats& stats) {
    stats = {};
    const std::size_t record = check_items(laz);
    if (request.point_count == 0) return;
    if (request.out.size() / record < request.point_count) {
        fail(std::nullopt, "output of " + std::to_string(request.out.size()) + " bytes cannot hold " +
                               std::to_string(request.point_count) + " records of " + std::to_string(record) +
                               " bytes");
    }
    const auto streams = split_layers(laz, request.bytes, record);
    ChunkPasses passes = build_passes(laz, streams, request.bytes.data(), request.fields);

    std::uint8_t* out = request.out.data();
    // With every field wanted, every byte is written; else the others are zeroed.
    run_passes(passes, out, request.point_count, record, (request.fields & fields::kEvery) != fields::kEvery);
    check_complete(passes);

    stats = collect_stats(streams, passes);
}

void decode_layered_chunk(const las::LaszipVlr& laz, const ChunkDecodeRequest& request) {
    LayeredChunkStats stats;
    decode_layered_chunk(laz, request, stats);
}

}  // namespace lidarscout::laz
