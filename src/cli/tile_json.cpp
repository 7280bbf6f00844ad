// Building the `info --json` objects.
#include "cli/diagnostic_output.hpp"
#include "cli/tile_json.hpp"

#include <cmath>

#include "core/error.hpp"
#include "core/text.hpp"
#include "geo/crs_definition.hpp"

namespace lidarscout::cli {
namespace {

using nlohmann::json;

json number_or_null(double v) { return std::isfinite(v) ? json(v) : json(nullptr); }

json lonlat_json(const std::optional<geo::LonLatBounds>& b) {
    if (!b) return nullptr;
    return {{"west", b->west}, {"south", b->south}, {"east", b->east}, {"north", b->north}};
}

json vec3(const std::array<double, 3>& a) {
    return json::array({number_or_null(a[0]), number_or_null(a[1]), number_or_null(a[2])});
}

json crs_json(const las::Crs& crs) {
    return {{"epsg", crs.epsg ? json(*crs.epsg) : json(nullptr)},
            {"vertical_epsg", crs.vertical_epsg ? json(*crs.vertical_epsg) : json(nullptr)},
            {"name", crs.name.empty() ? json(nullptr) : json(crs.name)},
            {"source", crs.source},
            {"horizontal_unit", las::unit_name(crs.horizontal_unit)},
            {"vertical_unit", las::unit_name(crs.vertical_unit)},
            {"to_metres", number_or_null(crs.horizontal_to_metres)},
            {"vertical_to_metres", number_or_null(crs.vertical_to_metres)},
            {"warnings", crs.warnings.messages()},
            {"diagnostics", diagnostics_json(crs.warnings)}};
}

json laz_json(const dataset::Tile& t) {
    if (!t.laz()) return nullptr;
    const las::LaszipVlr& laz = *t.laz();
    json items = json::array();
    for (const auto& it : laz.items) {
        items.push_back(
            {{"type", it.type}, {"name", las::item_type_name(it.type)}, {"size", it.size}, {"version", it.version}});
    }
    return {{"compressor", laz.compressor},
            {"coder", laz.coder},
            {"laszip_version", std::to_string(laz.version_major) + "." + std::to_string(laz.version_minor) + "r" +
                                   std::to_string(laz.version_revision)},
            {"chunk_size", laz.chunk_size},
            {"variable_chunks", laz.variable_chunks()},
            {"items", items},
            {"chunk_count", t.chunks() ? json(t.chunks()->size()) : json(nullptr)}};
}

json copc_json(const dataset::Tile& t) {
    if (!t.copc) return nullptr;
    const auto& c = *t.copc;
    return {{"center", {c.center[0], c.center[1], c.center[2]}},
            {"halfsize", c.halfsize},
            {"spacing", c.spacing},
            {"root_hierarchy_offset", c.root_hier_offset},
            {"root_hierarchy_size", c.root_hier_size},
            {"gpstime_range", {c.gpstime_min, c.gpstime_max}}};
}

json vlrs_json(const std::vector<las::Vlr>& vlrs) {
    json out = json::array();
    for (const auto& v : vlrs) {
        out.push_back({{"user_id", v.user_id}, {"record_id", v.record_id}, {"description", v.description},
                       {"offset", v.data_offset}, {"size", v.data_size}});
    }
    return out;
}

}  // namespace

namespace {

// Every string of `j` as display_text gives it.
void make_text_displayable(json& j) {
    if (j.is_string()) {
        j = display_text(j.get_ref<const std::string&>());
    } else if (j.is_structured()) {
        for (auto& v : j) make_text_displayable(v);
    }
}

}  // namespace

json tile_to_json(const dataset::Tile& t) {
    const auto& h = t.header;
    json j = {{"path", t.path()},
            {"file_size", t.file_size()},
            {"version", h.version_string()},
            {"header_size", h.header_size},
            {"offset_to_point_data", h.offset_to_point_data},
            {"point_format", h.point_format},
            {"record_length", h.record_length},
            {"point_count", h.point_count},
            {"scale", vec3(h.scale)},
            {"offset", vec3(h.offset)},
            {"bounds", {{"min", vec3(h.min)}, {"max", vec3(h.max)}}},
            {"system_identifier", h.system_identifier},
            {"generating_software", h.generating_software},
            {"creation", {{"day", h.creation_day}, {"year", h.creation_year}}},
            {"global_encoding", h.global_encoding},
            {"vlrs", vlrs_json(t.vlrs())},
            {"evlrs", vlrs_json(t.evlrs())},
            {"crs", crs_json(t.crs())},
            {"lonlat_bounds", lonlat_json(dataset::tile_lonlat_bounds(t))},
            {"laz", laz_json(t)},
            {"copc", copc_json(t)},
            {"warnings", t.warnings().messages()},
            {"diagnostics", diagnostics_json(t.warnings())},
            {"error", nullptr}};
    make_text_displayable(j);  // strings from the file may be Latin-1 or hold control bytes
    return j;
}

json chunks_to_json(const dataset::Tile& t) {
    json out = json::array();
    if (!t.chunks()) return out;
    for (const auto& c : *t.chunks()) {
        out.push_back({{"first_point", c.first_point}, {"point_count", c.point_count}, {"byte_offset", c.byte_offset},
                       {"byte_size", c.byte_size}});
    }
    return out;
}

json chunk_points_to_json(const std::vector<dataset::ChunkPoint>& points, const dataset::Tile& t) {
    const auto& fmt = las::point_format_info(t.header.point_format);
    json out = json::array();
    for (const auto& cp : points) {
        const auto& p = cp.point;
        json rgb = fmt.rgb_offset >= 0 ? json::array({p.rgb[0], p.rgb[1], p.rgb[2]}) : json(nullptr);
        out.push_back({{"index", cp.index},
                       {"X", p.X},
                       {"Y", p.Y},
                       {"Z", p.Z},
                       {"x", p.x},
                       {"y", p.y},
                       {"z", p.z},
                       {"intensity", p.intensity},
                       {"return_number", p.return_number},
                       {"number_of_returns", p.number_of_returns},
                       {"classification", p.classification},
                       {"scan_angle", p.scan_angle_raw},
                       {"user_data", p.user_data},
                       {"point_source_id", p.point_source_id},
                       {"gps_time", fmt.gps_offset >= 0 ? json(p.gps_time) : json(nullptr)},
                       {"rgb", rgb},
                       {"nir", fmt.nir_offset >= 0 ? json(p.nir) : json(nullptr)}});
    }
    return out;
}

json failed_tile_json(const std::string& path, const std::string& error) {
    json j = {{"path", display_text(path)}, {"error", display_text(error)}};
    for (const char* k : {"version", "point_format", "record_length", "point_count", "scale", "offset", "bounds", "crs",
                          "lonlat_bounds", "laz", "copc"}) {
        j[k] = nullptr;
    }
    return j;
}

nlohmann::json error_list_json(const std::vector<ErrorRecord>& errors) {
    auto list = nlohmann::json::array();
    for (const auto& e : errors) {
        nlohmann::json offset = nullptr;
        if (e.offset) offset = *e.offset;
        list.push_back({{"file", display_text(e.file)}, {"offset", offset}, {"cause", display_text(e.cause)}});
    }
    return list;
}

}  // namespace lidarscout::cli
