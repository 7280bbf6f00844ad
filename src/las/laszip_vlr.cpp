// Parsing and validation of the LASzip VLR payload: the fixed 34-byte part, then 6 bytes per
// item. Only combinations that a LAZ decoder can actually decode are accepted, so a file with
// an unknown compressor, coder, item type, size or version fails here with a precise cause.
#include "las/laszip_vlr.hpp"

#include <string>

#include "core/error.hpp"
#include "io/byte_reader.hpp"

namespace lidarscout::las {
namespace {

constexpr std::size_t kFixedPartSize = 34;
constexpr std::size_t kItemSize = 6;
constexpr std::size_t kItemListOffset = kFixedPartSize;  // items follow the fixed part
constexpr std::uint16_t kMaxCompressor = 3;              // 0 none .. 3 layered chunked
constexpr std::uint16_t kArithmeticCoder = 0;

// Which point layout an item belongs to: the LAS 1.0-1.3 formats (0-5) or 1.4 (6-10).
enum class Family { Point10, Point14 };

// What the format allows for one item type.
struct ItemRule {
    Family family;
    std::uint16_t size;          // required size; 0: any size of at least 1 (extra bytes)
    std::uint16_t min_version;
    std::uint16_t max_version;
};

// The item types a decoder knows; nullptr for the others (incl. the never-used 1-5).
const ItemRule* rule_for(std::uint16_t type) {
    static constexpr ItemRule kPoint10{Family::Point10, 20, 1, 2};
    static constexpr ItemRule kGpsTime11{Family::Point10, 8, 1, 2};
    static constexpr ItemRule kRgb12{Family::Point10, 6, 1, 2};
    static constexpr ItemRule kWavepacket13{Family::Point10, 29, 1, 1};
    static constexpr ItemRule kByte{Family::Point10, 0, 1, 2};
    static constexpr ItemRule kPoint14{Family::Point14, 30, 2, 4};
    static constexpr ItemRule kRgb14{Family::Point14, 6, 2, 4};
    static constexpr ItemRule kRgbNir14{Family::Point14, 8, 2, 4};
    static constexpr ItemRule kWavepacket14{Family::Point14, 29, 3, 4};
    static constexpr ItemRule kByte14{Family::Point14, 0, 2, 4};
    switch (static_cast<ItemType>(type)) {
        case ItemType::Point10: return &kPoint10;
        case ItemType::GpsTime11: return &kGpsTime11;
        case ItemType::Rgb12: return &kRgb12;
        case ItemType::Wavepacket13: return &kWavepacket13;
        case ItemType::Byte: return &kByte;
        case ItemType::Point14: return &kPoint14;
        case ItemType::Rgb14: return &kRgb14;
        case ItemType::RgbNir14: return &kRgbNir14;
        case ItemType::Wavepacket14: return &kWavepacket14;
        case ItemType::Byte14: return &kByte14;
        default: return nullptr;
    }
}

std::string versions_text(const ItemRule& rule) {
    if (rule.min_version == rule.max_version) return std::to_string(rule.min_version);
    return std::to_string(rule.min_version) + " to " + std::to_string(rule.max_version);
}

// Throws for VLR problems, naming the payload byte where the bad field lies.
class Checker {
public:
    Checker(const std::string& file, std::uint64_t payload_offset) : file_(file), base_(payload_offset) {}

    [[noreturn]] void fail(std::size_t field_pos, const std::string& cause) const {
        throw Error(file_, base_ + field_pos, "laszip VLR: " + cause);
    }

    void check_item(const LazItem& item, std::size_t index, std::size_t field_pos) const {
        const std::string what = "item " + std::to_string(index);
        const ItemRule* rule = rule_for(item.type);
        if (!rule) fail(field_pos, what + " has unknown type " + std::to_string(item.type));
        const std::string named = what + " (" + item_type_name(item.type) + ")";
        if (rule->size != 0 && item.size != rule->size) {
            fail(field_pos + 2, named + " has size " + std::to_string(item.size) + ", must be " +
                                    std::to_string(rule->size));
        }
        if (rule->size == 0 && item.size == 0) fail(field_pos + 2, named + " has size 0");
        if (item.version < rule->min_version || item.version > rule->max_version) {
            fail(field_pos + 4, named + " has unsupported version " + std::to_string(item.version) + " (" +
                                    versions_text(*rule) + " expected)");
        }
    }

    // One point item first, then only attributes of the same point layout; the layered
    // compressor is the only one for LAS 1.4 items and only for them.
    void check_layout(const LaszipVlr& vlr) const {
        const auto first = static_cast<ItemType>(vlr.items.front().type);
        if (first != ItemType::Point10 && first != ItemType::Point14) {
            fail(kItemListOffset, std::string("the first item is ") + item_type_name(vlr.items.front().type) +
                                      ", not POINT10 or POINT14");
        }
        const Family family = first == ItemType::Point10 ? Family::Point10 : Family::Point14;
        for (std::size_t i = 1; i < vlr.items.size(); ++i) {
            const auto type = static_cast<ItemType>(vlr.items[i].type);
            if (type == ItemType::Point10 || type == ItemType::Point14 ||
                rule_for(vlr.items[i].type)->family != family) {
                fail(kItemListOffset + i * kItemSize,
                     "item " + std::to_string(i) + " (" + item_type_name(vlr.items[i].type) + ") cannot follow " +
                         item_type_name(vlr.items.front().type));
            }
        }
        if (vlr.compressor == 3 && family != Family::Point14) {
            fail(0, "the layered compressor 3 needs POINT14 items, found POINT10");
        }
        if ((vlr.compressor == 1 || vlr.compressor == 2) && family != Family::Point10) {
            fail(0, "compressor " + std::to_string(vlr.compressor) +
                        " cannot code POINT14 items (they need the layered compressor 3)");
        }
    }

private:
    const std::string& file_;
    std::uint64_t base_;
};

}  // namespace

std::uint32_t LaszipVlr::record_length() const {
    std::uint32_t total = 0;
    for (const auto& item : items) total += item.size;
    return total;
}

const char* item_type_name(std::uint16_t type) {
    switch (static_cast<ItemType>(type)) {
        case ItemType::Byte: return "BYTE";
        case ItemType::Short: return "SHORT";
        case ItemType::Integer: return "INT";
        case ItemType::Long: return "LONG";
        case ItemType::Float: return "FLOAT";
        case ItemType::Double: return "DOUBLE";
        case ItemType::Point10: return "POINT10";
        case ItemType::GpsTime11: return "GPSTIME11";
        case ItemType::Rgb12: return "RGB12";
        case ItemType::Wavepacket13: return "WAVEPACKET13";
        case ItemType::Point14: return "POINT14";
        case ItemType::Rgb14: return "RGB14";
        case ItemType::RgbNir14: return "RGBNIR14";
        case ItemType::Wavepacket14: return "WAVEPACKET14";
        case ItemType::Byte14: return "BYTE14";
    }
    return "UNKNOWN";
}

LaszipVlr parse_laszip_vlr(std::span<const std::uint8_t> payload, const std::string& file,
                           std::uint64_t offset) {
    const Checker check(file, offset);
    if (payload.size() < kFixedPartSize) {
        check.fail(0, "payload of " + std::to_string(payload.size()) + " bytes is shorter than the " +
                          std::to_string(kFixedPartSize) + "-byte fixed part");
    }
    io::ByteReader r(payload, offset, file);
    LaszipVlr vlr;
    vlr.compressor = r.u16("laszip compressor");
    vlr.coder = r.u16("laszip coder");
    vlr.version_major = r.u8("laszip version");
    vlr.version_minor = r.u8("laszip version");
    vlr.version_revision = r.u16("laszip version");
    vlr.options = r.u32("laszip options");
    vlr.chunk_size = r.u32("laszip chunk size");
    vlr.number_of_special_evlrs = r.i64("laszip special EVLR count");
    vlr.offset_to_special_evlrs = r.i64("laszip special EVLR offset");
    const std::uint16_t num_items = r.u16("laszip item count");

    if (vlr.compressor > kMaxCompressor) check.fail(0, "unknown compressor " + std::to_string(vlr.compressor));
    if (vlr.coder != kArithmeticCoder) check.fail(2, "unknown coder " + std::to_string(vlr.coder));
    if (num_items == 0) check.fail(32, "no items");
    const std::size_t expected = kFixedPartSize + kItemSize * num_items;
    if (payload.size() != expected) {
        check.fail(32, "payload has " + std::to_string(payload.size()) + " bytes but " + std::to_string(num_items) +
                           " items need " + std::to_string(expected));
    }

    vlr.items.resize(num_items);
    for (std::size_t i = 0; i < num_items; ++i) {
        LazItem& item = vlr.items[i];
        item.type = r.u16("laszip item type");
        item.size = r.u16("laszip item size");
        item.version = r.u16("laszip item version");
        check.check_item(item, i, kItemListOffset + i * kItemSize);
    }
    check.check_layout(vlr);
    return vlr;
}

}  // namespace lidarscout::las
