// Reading a tile's metadata: header, VLRs, EVLRs, CRS, laszip VLR, chunk table, COPC info.
#include "dataset/tile.hpp"

#include "core/error.hpp"
#include "geo/projection.hpp"
#include "io/file.hpp"

namespace lidarscout::dataset {
namespace {

std::optional<las::LaszipVlr> read_laszip(const io::File& file, const Tile& t) {
    const las::Vlr* v = las::find_vlr(t.vlrs, "laszip encoded", 22204);
    if (!t.header.compressed) return std::nullopt;  // a stray laszip VLR does not make a LAZ
    if (!v) {
        throw Error(file.path(), 104,
                    "the point format has the compression bit set but the file has no laszip VLR");
    }
    auto laz = las::parse_laszip_vlr(v->data, file.path(), v->data_offset);
    if (laz.compressor == 0) {
        throw Error(file.path(), v->data_offset, "laszip VLR says compressor 0 (none) in a compressed file");
    }
    if (laz.record_length() != t.header.record_length) {
        throw Error(file.path(), v->data_offset,
                    "laszip items make " + std::to_string(laz.record_length()) + "-byte records but the header says " +
                        std::to_string(t.header.record_length));
    }
    return laz;
}

}  // namespace

Tile read_tile(const io::File& file, const TileOptions& options) {
    Tile t;
    t.path = file.path();
    t.file_size = file.size();
    t.header = las::read_header(file);
    t.vlrs = las::read_vlrs(file, t.header, &t.warnings);
    t.evlrs = las::read_evlrs(file, t.header);
    t.crs = las::read_crs(t.vlrs, t.evlrs, file, (t.header.global_encoding & 0x10) != 0);
    geo::fall_back_to_horizontal(t.crs);
    t.laz = read_laszip(file, t);
    t.copc = las::find_copc_info(t.vlrs, file.path());
    t.warnings.attribute_to(t.path);
    t.crs.warnings.attribute_to(t.path);
    if (t.laz && options.chunk_table) t.chunks = laz::read_chunk_table(file, t.header, *t.laz);
    return t;
}

}  // namespace lidarscout::dataset
