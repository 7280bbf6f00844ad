// CRS records written by lidarscout: the key directory in its smallest form, the WKT as LAS 1.4 has it.
#include "las/crs_records.hpp"

#include <cstdint>
#include <vector>

namespace lidarscout::las {

CrsForm crs_record_form(const Vlr& v) {
    if (v.user_id == "liblas" && v.record_id == 2112) return CrsForm::LiblasWkt;
    if (v.user_id != "LASF_Projection") return CrsForm::None;
    if (v.record_id >= 34735 && v.record_id <= 34737) return CrsForm::GeoTiff;
    if (v.record_id == 2111 || v.record_id == 2112) return CrsForm::Wkt;
    return CrsForm::None;
}

bool is_crs_record(const Vlr& v) { return crs_record_form(v) != CrsForm::None; }

Vlr geotiff_epsg_vlr(int epsg, int vertical_epsg, bool geographic) {
    // Header (version 1, revision 1.0, key count), then GTModelType = projected (1) or geographic (2),
    // ProjectedCSType or GeographicType = epsg and VerticalCSType = vertical_epsg: each key id,
    // location 0 (the value is inline), count 1, value; in the order of their ids.
    const std::uint16_t model = geographic ? 2 : 1, type_key = geographic ? 2048 : 3072;
    std::vector<std::uint16_t> keys = {1, 1, 0, 2, 1024, 0, 1, model, type_key, 0, 1, static_cast<std::uint16_t>(epsg)};
    if (vertical_epsg) {
        keys[3] = 3;
        for (const int k : {4096, 0, 1, vertical_epsg}) keys.push_back(static_cast<std::uint16_t>(k));
    }
    Vlr v;
    v.user_id = "LASF_Projection";
    v.record_id = 34735;
    v.description = "GeoTIFF GeoKeyDirectoryTag";
    for (const std::uint16_t k : keys) {
        v.data.push_back(static_cast<std::uint8_t>(k & 0xff));
        v.data.push_back(static_cast<std::uint8_t>(k >> 8));
    }
    v.data_size = v.data.size();
    v.data_loaded = true;
    return v;
}

Vlr wkt_vlr(const std::string& wkt) {
    Vlr v;
    v.user_id = "LASF_Projection";
    v.record_id = 2112;
    v.description = "OGC WKT (lidarscout)";
    v.data.assign(wkt.begin(), wkt.end());
    v.data.push_back(0);
    v.data_size = v.data.size();
    v.data_loaded = true;
    return v;
}

}  // namespace lidarscout::las
