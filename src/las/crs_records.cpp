// CRS records written by lidarscout: the key directory in its smallest form, the WKT as LAS 1.4 has it.
#include "las/crs_records.hpp"

#include <cstdint>
#include <vector>

namespace lidarscout::las {

bool is_crs_record(const Vlr& v) {
    return v.user_id == "LASF_Projection" && ((v.record_id >= 34735 && v.record_id <= 34737) || v.record_id == 2111 ||
                                              v.record_id == 2112);
}

Vlr geotiff_epsg_vlr(int epsg, int vertical_epsg) {
    // Header (version 1, revision 1.0, key count), then GTModelType = projected, ProjectedCSType = epsg
    // and VerticalCSType = vertical_epsg: each key id, location 0 (the value is inline), count 1, value.
    std::vector<std::uint16_t> keys = {1, 1, 0, 2, 1024, 0, 1, 1, 3072, 0, 1, static_cast<std::uint16_t>(epsg)};
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
