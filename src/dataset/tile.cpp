// Reading a tile's metadata: header, VLRs, EVLRs, CRS, laszip VLR, chunk table, COPC info.
#include "dataset/tile.hpp"

#include <algorithm>

#include "core/error.hpp"
#include "geo/crs_definition.hpp"
#include "geo/projection.hpp"
#include "io/file.hpp"

namespace lidarscout::dataset {
namespace {

std::optional<las::LaszipVlr> read_laszip(const io::File& file, const las::Header& header,
                                          const std::vector<las::Vlr>& vlrs) {
    const las::Vlr* v = las::find_vlr(vlrs, "laszip encoded", 22204);
    if (!header.compressed) return std::nullopt;  // a stray laszip VLR does not make a LAZ
    if (!v) {
        throw Error(file.path(), 104,
                    "the point format has the compression bit set but the file has no laszip VLR");
    }
    auto laz = las::parse_laszip_vlr(v->data, file.path(), v->data_offset);
    if (laz.compressor == 0) {
        throw Error(file.path(), v->data_offset, "laszip VLR says compressor 0 (none) in a compressed file");
    }
    if (laz.record_length() != header.record_length) {
        throw Error(file.path(), v->data_offset,
                    "laszip items make " + std::to_string(laz.record_length()) + "-byte records but the header says " +
                        std::to_string(header.record_length));
    }
    return laz;
}

std::size_t hash_vlrs(const std::vector<las::Vlr>& vlrs, std::size_t seed) {
    const auto mix = [&seed](std::size_t h) { seed ^= h + 0x9e3779b97f4a7c15ull + (seed << 6) + (seed >> 2); };
    for (const auto& v : vlrs) {
        mix(std::hash<std::string>{}(v.user_id));
        mix(v.record_id);
        mix(v.header_offset);
        const auto* bytes = reinterpret_cast<const char*>(v.data.data());
        mix(std::hash<std::string_view>{}(std::string_view(bytes, v.data.size())));
    }
    return seed;
}

bool payloads_loaded(const std::vector<las::Vlr>& evlrs) {
    return std::all_of(evlrs.begin(), evlrs.end(), [](const las::Vlr& e) { return e.data_loaded; });
}

}  // namespace

std::shared_ptr<const TileRecords> SharedRecords::held_alike(
    const std::vector<las::Vlr>& vlrs, const std::vector<las::Vlr>& evlrs, bool wkt_flag,
    const std::function<bool(const TileRecords&)>& alike) const {
    auto [first, last] = entries_.equal_range(hash_vlrs(evlrs, hash_vlrs(vlrs, wkt_flag)));
    for (auto it = first; it != last; ++it) {
        const Entry& e = it->second;
        if (e.wkt_flag == wkt_flag && e.records->vlrs == vlrs && e.records->evlrs == evlrs && alike(*e.records)) {
            return e.records;
        }
    }
    return nullptr;
}

std::shared_ptr<const TileRecords> SharedRecords::find(const std::vector<las::Vlr>& vlrs,
                                                       const std::vector<las::Vlr>& evlrs, bool wkt_flag) const {
    if (!payloads_loaded(evlrs)) return nullptr;
    std::lock_guard lock(mutex_);
    return held_alike(vlrs, evlrs, wkt_flag, [](const TileRecords& a) { return a.crs.warnings.empty(); });
}

std::shared_ptr<const TileRecords> SharedRecords::intern(std::shared_ptr<const TileRecords> records, bool wkt_flag) {
    if (!payloads_loaded(records->evlrs)) return records;
    std::lock_guard lock(mutex_);
    const auto alike = [&](const TileRecords& a) {
        return a.laz == records->laz && a.crs.warnings == records->crs.warnings;
    };
    if (auto held = held_alike(records->vlrs, records->evlrs, wkt_flag, alike)) return held;
    entries_.emplace(hash_vlrs(records->evlrs, hash_vlrs(records->vlrs, wkt_flag)), Entry{records, wkt_flag});
    return records;
}

std::size_t SharedRecords::size() const {
    std::lock_guard lock(mutex_);
    return entries_.size();
}

Tile read_tile(const io::File& file, const TileOptions& options) {
    Tile t;
    auto f = std::make_shared<TileFile>();
    auto r = std::make_shared<TileRecords>();
    f->path = file.path();
    f->file_size = file.size();
    f->overview = options.overview;
    t.header = las::read_header(file);
    const bool wkt_flag = (t.header.global_encoding & 0x10) != 0;
    r->vlrs = las::read_vlrs(file, t.header, &f->warnings);
    r->evlrs = las::read_evlrs(file, t.header);
    // Records equal to ones shared before, whose CRS came without a warning, give theirs: the CRS read from the
    // same records is the same (a catalog's tiles mostly share theirs; read_crs was a sixth of read_tile in a
    // country's open from its overview sidecar).
    auto known = options.shared_records ? options.shared_records->find(r->vlrs, r->evlrs, wkt_flag) : nullptr;
    const auto read_crs = [&] {
        r->crs = las::read_crs(r->vlrs, r->evlrs, file, wkt_flag);
        geo::fall_back_to_horizontal(r->crs);
        r->crs.warnings.attribute_to(f->path);
    };
    if (!known) read_crs();
    r->laz = read_laszip(file, t.header, r->vlrs);
    if (known && known->laz != r->laz) known = nullptr, read_crs();  // (the same VLRs in a LAS file)
    t.copc = las::find_copc_info(r->vlrs, file.path());
    f->warnings.attribute_to(f->path);
    if (r->laz && options.chunk_table) f->chunks = laz::read_chunk_table(file, t.header, *r->laz);
    if (known) {
        f->records = std::move(known);
    } else {
        f->records = options.shared_records ? options.shared_records->intern(std::move(r), wkt_flag) : std::move(r);
    }
    t.file = std::move(f);
    return t;
}

std::optional<geo::LonLatBounds> tile_lonlat_bounds(const Tile& tile) {
    const std::string def = geo::crs_definition(tile.crs());
    if (def.empty() || tile.header.point_count == 0) return std::nullopt;
    const auto& h = tile.header;
    try {
        return geo::lonlat_bounds(def, h.min[0], h.min[1], h.max[0], h.max[1]);
    } catch (const Error&) {
        return std::nullopt;  // a CRS PROJ does not know: the file's CRS report says what it is
    }
}

}  // namespace lidarscout::dataset
