// write_crs and keep_crs: which form the output's point format wants, the record of that form made
// (through PROJ for WKT) before any record is dropped, and the records of the other forms named.
#include "pipelines/output_records.hpp"

#include <fmt/format.h>

#include <algorithm>

#include "core/error.hpp"
#include "geo/crs_definition.hpp"
#include "geo/projection.hpp"
#include "las/crs_records.hpp"
#include "las/point_format.hpp"

namespace lidarscout::pipelines {
namespace {

constexpr std::uint16_t kWktBit = 0x10;  // global encoding bit 4: the CRS is WKT

bool format_wants_wkt(const las::Header& h) { return las::point_format_info(h.point_format).extended; }

void set_wkt_bit(las::Header& h, bool wkt) {
    h.global_encoding = static_cast<std::uint16_t>(wkt ? h.global_encoding | kWktBit : h.global_encoding & ~kWktBit);
}

// The one record stating `definition` in the form the header wants; whether it is WKT.
std::pair<las::Vlr, bool> crs_record(const las::Header& h, const std::string& definition, const std::string& stage) {
    const geo::EpsgCodes codes = geo::epsg_codes_of_definition(definition);
    const bool wkt = format_wants_wkt(h) || (!codes.horizontal && h.at_least(1, 4));
    if (!wkt && !codes.horizontal) {
        throw Error::in_stage(stage, fmt::format("the output (point format {}, LAS {}) can name its CRS only by an "
                                                 "EPSG code and the CRS has none: choose one with --crs EPSG:n",
                                                 h.point_format, h.version_string()));
    }
    if (!wkt) {
        const bool geographic = geo::crs_info(definition).geographic;
        return {las::geotiff_epsg_vlr(codes.horizontal, codes.vertical, geographic), false};
    }
    try {
        return {las::wkt_vlr(geo::crs_wkt1(definition)), true};
    } catch (const Error& e) {
        throw Error::in_stage(stage, std::string("the CRS cannot be written as WKT: ") + e.what());
    }
}

std::string record_name(const las::Vlr& v) {
    return fmt::format("the {} {} {}", v.user_id, v.record_id, v.extended ? "EVLR" : "VLR");
}

}  // namespace

bool is_copc_record(const las::Vlr& v) { return v.user_id == "copc"; }

void write_crs(las::Header& h, std::vector<las::Vlr>& vlrs, std::vector<las::Vlr>& evlrs,
               const std::string& definition, const std::string& stage) {
    auto [record, wkt] = crs_record(h, definition, stage);  // (throws with every record still there)
    std::erase_if(vlrs, las::is_crs_record);
    std::erase_if(evlrs, las::is_crs_record);
    vlrs.push_back(std::move(record));
    set_wkt_bit(h, wkt);
}

std::vector<std::string> keep_crs(las::Header& h, std::vector<las::Vlr>& vlrs, std::vector<las::Vlr>& evlrs,
                                  const las::Crs& crs, const std::string& stage) {
    if (crs.source == "none") {  // (LAS 1.4 sets the bit for formats 6-10 whatever their CRS)
        if (format_wants_wkt(h)) set_wkt_bit(h, true);
        return {};
    }
    const las::CrsForm form = crs.source == "wkt" ? las::CrsForm::Wkt : las::CrsForm::GeoTiff;
    if (form == las::CrsForm::GeoTiff && format_wants_wkt(h)) {
        const std::string definition = geo::crs_definition(crs);
        write_crs(h, vlrs, evlrs, definition, stage);
        return {fmt::format("GeoTIFF keys replaced by the WKT of {} (LAS 1.4 requires WKT for point format {})",
                            definition, h.point_format)};
    }
    // GeoTIFF keys without an EPSG code (user-defined) keep the WKT beside them: it is what names the
    // CRS to PROJ (crs_definition); liblas's copy goes when that WKT is there.
    const bool keys_name_it = form == las::CrsForm::Wkt || crs.epsg.has_value();
    const auto is_wkt = [](const las::Vlr& v) { return las::crs_record_form(v) == las::CrsForm::Wkt; };
    const bool has_wkt =
        std::any_of(vlrs.begin(), vlrs.end(), is_wkt) || std::any_of(evlrs.begin(), evlrs.end(), is_wkt);
    std::string dropped;
    const auto other_form = [&](const las::Vlr& v) {
        const las::CrsForm f = las::crs_record_form(v);
        const bool needed = f == las::CrsForm::Wkt || (f == las::CrsForm::LiblasWkt && !has_wkt);
        if (f == las::CrsForm::None || f == form || (!keys_name_it && needed)) return false;
        dropped += (dropped.empty() ? "" : ", ") + record_name(v);
        return true;
    };
    std::erase_if(vlrs, other_form);
    std::erase_if(evlrs, other_form);
    set_wkt_bit(h, form == las::CrsForm::Wkt && h.at_least(1, 4));
    if (dropped.empty()) return {};
    return {"dropped " + dropped + ": the CRS is stated once, by the " +
            (form == las::CrsForm::Wkt ? "WKT record" : "GeoTIFF keys") + " (" + geo::crs_definition(crs) + ")"};
}

std::vector<std::string> keep_crs_or_keys(las::Header& h, std::vector<las::Vlr>& vlrs, std::vector<las::Vlr>& evlrs,
                                          const las::Crs& crs, const std::string& stage, const std::string& file,
                                          bool force, std::string& forced) {
    try {
        return keep_crs(h, vlrs, evlrs, crs, stage);
    } catch (const Error& e) {
        const std::string what = fmt::format("point format {} needs the CRS as WKT: {}", h.point_format, e.what());
        if (!force) throw Error(file, std::nullopt, what + "; nothing written (--force keeps the GeoTIFF keys)");
        forced = what;
        return {};
    }
}

}  // namespace lidarscout::pipelines
