// Reading a tile's metadata: header, VLRs, EVLRs, CRS, laszip VLR, chunk table, COPC info.
#include "dataset/tile.hpp"

#include "core/error.hpp"
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

}  // namespace

Tile read_tile(const io::File& file, const TileOptions& options) {
    Tile t;
    auto f = std::make_shared<TileFile>();
    auto r = std::make_shared<TileRecords>();
    f->path = file.path();
    f->file_size = file.size();
    t.header = las::read_header(file);
    r->vlrs = las::read_vlrs(file, t.header, &f->warnings);
    r->evlrs = las::read_evlrs(file, t.header);
    r->crs = las::read_crs(r->vlrs, r->evlrs, file, (t.header.global_encoding & 0x10) != 0);
    geo::fall_back_to_horizontal(r->crs);
    r->laz = read_laszip(file, t.header, r->vlrs);
    t.copc = las::find_copc_info(r->vlrs, file.path());
    f->warnings.attribute_to(f->path);
    r->crs.warnings.attribute_to(f->path);
    if (r->laz && options.chunk_table) f->chunks = laz::read_chunk_table(file, t.header, *r->laz);
    f->records = std::move(r);
    t.file = std::move(f);
    return t;
}

}  // namespace lidarscout::dataset
