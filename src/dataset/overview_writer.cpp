// The overview sidecar writer: each tile's metadata bytes (checked by reading the tile back from them)
// and chunk-point records read in parallel, the tiles put in Hilbert order, their records moved to the
// sidecar's offset and tagged with their tile, then written as LAZ with the tile table as an EVLR.
#include "dataset/overview_writer.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <ctime>
#include <map>
#include <optional>
#include <tuple>

#include "core/error.hpp"
#include "core/thread_pool.hpp"
#include "dataset/chunk_points.hpp"
#include "dataset/overview_sidecar.hpp"
#include "io/file.hpp"
#include "las/header_writer.hpp"
#include "las/point_format.hpp"
#include "las/vlr.hpp"
#include "laz/laz.hpp"

namespace lidarscout::dataset {
namespace {

constexpr std::uint64_t kMaxTail = 1u << 20;  // a tile whose last bytes to keep pass this is left out
constexpr std::size_t kDescriptor = 192;      // an Extra Bytes VLR's descriptor

// One tile as the sidecar will hold it (entry unset: left out).
struct Made {
    std::optional<OverviewEntry> entry;
    std::vector<std::uint8_t> records;  // its chunk points, its own format
};

bool same_copc(const std::optional<las::CopcInfo>& a, const std::optional<las::CopcInfo>& b) {
    if (!a || !b) return !a && !b;
    return std::memcmp(a->center, b->center, sizeof a->center) == 0 && a->halfsize == b->halfsize &&
           a->spacing == b->spacing && a->root_hier_offset == b->root_hier_offset &&
           a->root_hier_size == b->root_hier_size;
}

bool same_tile(const Tile& a, const Tile& b) {
    const bool chunks = a.chunks().has_value() == b.chunks().has_value() &&
                        (!a.chunks() || (a.chunks()->chunks() == b.chunks()->chunks() &&
                                         a.chunks()->table_offset == b.chunks()->table_offset));
    return chunks && las::serialize_header(a.header) == las::serialize_header(b.header) && a.vlrs() == b.vlrs() &&
           a.evlrs() == b.evlrs() && a.laz() == b.laz() && same_copc(a.copc, b.copc);
}

// Where the bytes read_tile reads at a file's end begin: its chunk table's, its EVLRs'.
std::uint64_t tail_start(const Tile& t, std::uint64_t size) {
    std::uint64_t at = size;
    if (const auto& c = t.chunks(); c && c->table_offset > 0) {
        at = c->offset_from_file_end ? std::min(c->table_offset, size - std::min<std::uint64_t>(size, 8))
                                     : c->table_offset;
    }
    if (t.header.number_of_evlrs > 0 && t.header.evlr_offset > 0) at = std::min(at, t.header.evlr_offset);
    return std::min(at, size);
}

// The entry's head and tail: the tile's header (as it is in the dataset: a virtual tile's moved),
// VLRs and chunk-table pointer, its last bytes. False when they do not give the tile back.
bool take_image(const Tile& t, const io::File& file, OverviewEntry& e) {
    const auto& h = t.header;
    const std::uint16_t standard = las::standard_header_size(h.version_major, h.version_minor);
    std::vector<std::uint8_t> trailing;
    if (h.header_size > standard) trailing = file.read_vector(standard, h.header_size - standard, "header");
    e.head = las::serialize_header(h, trailing);
    const std::uint64_t pointer = t.compressed() ? 8 : 0;
    const std::uint64_t end = std::min<std::uint64_t>(h.offset_to_point_data + pointer, file.size());
    const auto rest = file.read_vector(h.header_size, end - h.header_size, "VLRs");
    e.head.insert(e.head.end(), rest.begin(), rest.end());
    constexpr std::size_t kCopcCentre = 54;  // the COPC info VLR (the first) starts with its x, y centre
    if (t.copc && e.head.size() >= h.header_size + kCopcCentre + 16) {  // (a virtual tile's, moved)
        std::memcpy(e.head.data() + h.header_size + kCopcCentre, t.copc->center, 16);
    }
    const std::uint64_t from = tail_start(t, file.size());
    if (file.size() - from > kMaxTail) return false;
    e.tail = file.read_vector(from, file.size() - from, "chunk table");
    try {
        return same_tile(read_tile(io::File::in_memory(t.path(), file.size(), e.head, e.tail)), t);
    } catch (const Error&) {
        return false;  // read_tile read elsewhere: the tile is read itself
    }
}

// `given`: the tile's chunk points already read (then none is read here), or null.
Made make(const DatasetTile& t, const std::string& id, std::uint64_t las_stride, std::vector<std::uint8_t>* given) {
    Made m;
    try {
        const io::File file = io::File::open(t.tile.path());
        OverviewEntry e;
        e.id = id;
        e.made_from = file_validator(file);
        if (!take_image(t.tile, file, e)) return m;
        const std::uint16_t length = t.tile.header.record_length;
        if (given) {
            if (given->size() % length == 0) m.records = std::move(*given);
            m.entry = std::move(e);
            return m;
        }
        for (const auto& at : chunk_point_locations(t.tile, las_stride)) {
            const auto record = file.read_vector(at.offset, length, "chunk point");
            m.records.insert(m.records.end(), record.begin(), record.end());
        }
        m.entry = std::move(e);
    } catch (const Error&) {
        m.records.clear();  // unreadable now: left out, read (and reported) when opened
    }
    return m;
}

std::vector<std::size_t> hilbert_order(const Dataset& ds) {
    const double w = std::max(ds.bounds_m.max_x - ds.bounds_m.min_x, 1e-9);
    const double h = std::max(ds.bounds_m.max_y - ds.bounds_m.min_y, 1e-9);
    const auto cell = [](double v) { return static_cast<std::uint32_t>(std::clamp(v, 0.0, 1.0) * 65535.0); };
    std::vector<std::pair<std::uint64_t, std::size_t>> keys;
    for (std::size_t i = 0; i < ds.tiles.size(); ++i) {
        const auto& b = ds.tiles[i].bounds_m;
        const double x = b.empty() ? 0.0 : (b.centre_x() - ds.bounds_m.min_x) / w;
        const double y = b.empty() ? 0.0 : (b.centre_y() - ds.bounds_m.min_y) / h;
        keys.emplace_back(hilbert_index(cell(x), cell(y)), i);
    }
    std::sort(keys.begin(), keys.end());
    std::vector<std::size_t> order;
    for (const auto& [key, i] : keys) order.push_back(i);
    return order;
}

// The kind of records the sidecar holds: the most common (format, record length, scale) of the tiles.
using Kind = std::tuple<std::uint8_t, std::uint16_t, std::array<double, 3>>;
Kind kind_of(const Tile& t) { return {t.header.point_format, t.header.record_length, t.header.scale}; }

std::optional<Kind> common_kind(const Dataset& ds, const std::vector<Made>& made) {
    std::map<Kind, std::size_t> count;
    for (std::size_t i = 0; i < made.size(); ++i) {
        if (made[i].entry && !made[i].records.empty()) ++count[kind_of(ds.tiles[i].tile)];
    }
    if (count.empty()) return std::nullopt;
    return std::max_element(count.begin(), count.end(), [](auto& a, auto& b) { return a.second < b.second; })->first;
}

// The tile's integer delta to the sidecar's offset on each axis; nullopt when an offset is not a
// whole number of steps away or a point would not fit the sidecar's integers.
std::optional<std::array<std::int64_t, 3>> delta_of(const Tile& t, const las::Header& s, const Made& m) {
    std::array<std::int64_t, 3> d{};
    for (int a = 0; a < 3; ++a) {
        const double steps = (t.header.offset[a] - s.offset[a]) / s.scale[a];
        if (!(std::abs(steps) < 1e15) || std::abs(steps - std::round(steps)) > 1e-3) return std::nullopt;
        d[a] = static_cast<std::int64_t>(std::llround(steps));
    }
    const std::size_t length = t.header.record_length;
    for (std::size_t p = 0; p < m.records.size(); p += length) {
        for (int a = 0; a < 3; ++a) {
            std::int32_t v = 0;
            std::memcpy(&v, m.records.data() + p + 4 * a, 4);
            const std::int64_t moved = std::int64_t{v} + d[a];
            if (moved < INT32_MIN || moved > INT32_MAX) return std::nullopt;
        }
    }
    return d;
}

void put_tile(std::vector<std::uint8_t>& out, std::uint32_t k) {
    const auto* b = reinterpret_cast<const std::uint8_t*>(&k);
    out.insert(out.end(), b, b + 4);
}

// The tile's records moved by `d` and tagged with `k`, appended to `out`; the header's bounds extended.
void add_records(const Made& m, std::size_t length, const std::array<std::int64_t, 3>& d, std::uint32_t k,
                 std::vector<std::uint8_t>& out, las::Header& h) {
    for (std::size_t p = 0; p < m.records.size(); p += length) {
        const std::size_t at = out.size();
        out.insert(out.end(), m.records.begin() + p, m.records.begin() + p + length);
        for (int a = 0; a < 3; ++a) {
            std::int32_t v = 0;
            std::memcpy(&v, out.data() + at + 4 * a, 4);
            v = static_cast<std::int32_t>(v + d[a]);
            std::memcpy(out.data() + at + 4 * a, &v, 4);
            const double c = v * h.scale[a] + h.offset[a];
            h.min[a] = std::min(h.min[a], c), h.max[a] = std::max(h.max[a], c);
        }
        put_tile(out, k);
    }
}

// An Extra Bytes descriptor (LAS 1.4: 192 bytes) of `type` (0: `options` undocumented bytes).
std::vector<std::uint8_t> descriptor(std::uint8_t type, std::uint8_t options, const std::string& name,
                                     const std::string& description) {
    std::vector<std::uint8_t> d(kDescriptor, 0);
    d[2] = type, d[3] = options;
    std::memcpy(d.data() + 4, name.data(), std::min<std::size_t>(name.size(), 32));
    std::memcpy(d.data() + 160, description.data(), std::min<std::size_t>(description.size(), 32));
    return d;
}

// The model tile's extra bytes (its own descriptors, else one undocumented field) and the tile index.
las::Vlr extra_bytes_vlr(const Tile& model) {
    las::Vlr v;
    v.user_id = "LASF_Spec", v.record_id = 4, v.description = "extra bytes";
    const std::size_t extra = model.header.record_length - las::point_format_info(model.header.point_format).size;
    if (const las::Vlr* own = las::find_vlr(model.vlrs(), "LASF_Spec", 4); own && extra > 0) {
        v.data = own->data;
    } else if (extra > 0) {
        v.data = descriptor(0, static_cast<std::uint8_t>(extra), "tile extra bytes", "as in the tiles");
    }
    const auto tile = descriptor(5, 0, "tile", "index in the overview tile table");
    v.data.insert(v.data.end(), tile.begin(), tile.end());
    return v;
}

// The sidecar's header and VLRs: LAS 1.4, the model tile's format, scale, offset and CRS records.
las::Header sidecar_header(const Tile& model, std::vector<las::Vlr>& vlrs) {
    las::Header h;
    h.version_major = 1, h.version_minor = 4;
    h.header_size = las::standard_header_size(1, 4);
    h.point_format = model.header.point_format;
    h.record_length = static_cast<std::uint16_t>(model.header.record_length + kOverviewTileField);
    h.scale = model.header.scale, h.offset = model.header.offset;
    h.global_encoding = model.header.global_encoding & 0x10;  // the CRS records' kind (WKT)
    h.system_identifier = "lidarscout overview sidecar";
    h.generating_software = "lidarscout catalog --overview";
    const std::time_t now = std::time(nullptr);
    std::tm t{};
    gmtime_r(&now, &t);
    h.creation_year = static_cast<std::uint16_t>(t.tm_year + 1900);
    h.creation_day = static_cast<std::uint16_t>(t.tm_yday + 1);
    for (int a = 0; a < 3; ++a) h.min[a] = INFINITY, h.max[a] = -INFINITY;
    for (const auto& v : model.vlrs()) {
        if (v.user_id == "LASF_Projection") vlrs.push_back(v);
    }
    vlrs.push_back(extra_bytes_vlr(model));
    return h;
}

// The sidecar of the tiles made (their records moved from), in Hilbert order.
OverviewWriteResult write_made(const Dataset& ds, std::vector<Made>& made, const std::string& output,
                               const std::string& protect) {
    const std::vector<std::size_t> order = hilbert_order(ds);
    const auto kind = common_kind(ds, made);
    const Tile* model = nullptr;
    for (const std::size_t i : order) {
        if (kind && !model && made[i].entry && !made[i].records.empty() && kind_of(ds.tiles[i].tile) == *kind) {
            model = &ds.tiles[i].tile;
        }
    }
    std::vector<las::Vlr> vlrs;
    las::Header header = model ? sidecar_header(*model, vlrs) : sidecar_header(ds.tiles.at(order.at(0)).tile, vlrs);
    OverviewWriteResult result;
    std::vector<OverviewEntry> entries;
    std::vector<std::uint8_t> records;
    for (const std::size_t i : order) {
        Made& m = made[i];
        if (!m.entry) {
            ++result.left_out;
            continue;
        }
        OverviewEntry& e = *m.entry;
        e.first_point = result.points;
        const Tile& tile = ds.tiles[i].tile;
        const auto d = model && kind_of(tile) == *kind ? delta_of(tile, header, m) : std::nullopt;
        if (d && !m.records.empty()) {
            e.delta = *d;
            e.points = static_cast<std::uint32_t>(m.records.size() / ds.tiles[i].tile.header.record_length);
            add_records(m, ds.tiles[i].tile.header.record_length, *d, static_cast<std::uint32_t>(entries.size()),
                        records, header);
            result.points += e.points;
            ++result.held;
        }
        m.records = {};
        entries.push_back(std::move(e));
    }
    result.tiles = entries.size();
    if (result.points == 0) header.min = header.max = {0, 0, 0};
    laz::LasWriter writer(output, header, vlrs, {}, ThreadPool::shared(), {}, protect);
    writer.header().min = header.min, writer.header().max = header.max;
    writer.add(records);
    records = {};
    las::Vlr table;
    table.user_id = kOverviewUser, table.record_id = kOverviewTableRecord, table.extended = true;
    table.description = "overview tile table";
    table.data = serialize_overview_table(entries);
    result.bytes = writer.finish({table}).bytes_written;
    return result;
}

}  // namespace

std::uint64_t hilbert_index(std::uint32_t x, std::uint32_t y) {
    std::uint64_t d = 0;
    for (std::uint32_t s = 1u << 15; s > 0; s >>= 1) {
        const std::uint32_t rx = (x & s) ? 1 : 0, ry = (y & s) ? 1 : 0;
        d += std::uint64_t{s} * s * ((3 * rx) ^ ry);
        if (ry == 0) {  // rotate the quadrant
            if (rx == 1) x = (s - 1) - (x & (s - 1)), y = (s - 1) - (y & (s - 1));
            std::swap(x, y);
        }
    }
    return d;
}

OverviewWriteResult write_overview(const Dataset& ds, std::span<const std::string> ids, const std::string& output,
                                   const std::string& protect) {
    if (ids.size() != ds.tiles.size()) throw Error("internal: an overview needs an id per tile");
    std::vector<Made> made(ds.tiles.size());
    ThreadPool::shared().for_each(made.size(),
                                  [&](std::size_t i) { made[i] = make(ds.tiles[i], ids[i], ds.las_stride, nullptr); });
    return write_made(ds, made, output, protect);
}

OverviewWriteResult write_overview(const Dataset& ds, std::span<const std::string> ids,
                                   std::span<std::vector<std::uint8_t>> records, const std::string& output) {
    if (ids.size() != ds.tiles.size() || records.size() != ds.tiles.size()) {
        throw Error("internal: an overview needs an id and records per tile");
    }
    std::vector<Made> made(ds.tiles.size());
    ThreadPool::shared().for_each(made.size(), [&](std::size_t i) {
        made[i] = make(ds.tiles[i], ids[i], ds.las_stride, &records[i]);
    });
    return write_made(ds, made, output, {});
}

}  // namespace lidarscout::dataset
