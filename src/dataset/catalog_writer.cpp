// A dataset as a virtual point cloud: one STAC item per tile (ids unique, hrefs relative to the
// catalog's folder), written through a temporary name.
#include "dataset/catalog_writer.hpp"

#include <chrono>
#include <cstdio>
#include <ctime>
#include <filesystem>
#include <algorithm>
#include <set>

#include <nlohmann/json.hpp>

#include "core/error.hpp"
#include "dataset/stac_catalog.hpp"
#include "geo/crs_definition.hpp"
#include "geo/projection.hpp"
#include "io/output_file.hpp"
#include "net/url.hpp"

namespace lidarscout::dataset {

namespace fs = std::filesystem;
using nlohmann::json;
using nlohmann::ordered_json;

namespace {

constexpr const char* kPointcloudExtension = "https://stac-extensions.github.io/pointcloud/v1.0.0/schema.json";
constexpr const char* kProjectionExtension = "https://stac-extensions.github.io/projection/v1.1.0/schema.json";

bool has_gps_time(int f) { return f == 1 || f >= 3; }
bool has_rgb(int f) { return f == 2 || f == 3 || f == 5 || f == 7 || f == 8 || f == 10; }
bool has_nir(int f) { return f == 8 || f == 10; }
bool has_waveform(int f) { return f == 4 || f == 5 || f == 9 || f == 10; }

// The dimensions of a point format, named as PDAL names them (what QGIS shows).
json point_schema(int format) {
    json out = json::array();
    const auto add = [&](const char* name, const char* type, int size) {
        out.push_back({{"name", name}, {"size", size}, {"type", type}});
    };
    for (const char* axis : {"X", "Y", "Z"}) add(axis, "floating", 8);
    add("Intensity", "unsigned", 2);
    add("ReturnNumber", "unsigned", 1);
    add("NumberOfReturns", "unsigned", 1);
    add("ScanDirectionFlag", "unsigned", 1);
    add("EdgeOfFlightLine", "unsigned", 1);
    add("Classification", "unsigned", 1);
    add("ScanAngleRank", "floating", 4);
    add("UserData", "unsigned", 1);
    add("PointSourceId", "unsigned", 2);
    if (format >= 6) add("ScanChannel", "unsigned", 1), add("ClassFlags", "unsigned", 1);
    if (has_gps_time(format)) add("GpsTime", "floating", 8);
    if (has_rgb(format)) add("Red", "unsigned", 2), add("Green", "unsigned", 2), add("Blue", "unsigned", 2);
    if (has_nir(format)) add("Infrared", "unsigned", 2);
    if (has_waveform(format)) {
        add("WavePacketDescriptorIndex", "unsigned", 1);
        add("WaveformDataOffset", "unsigned", 8);
        add("WaveformPacketSize", "unsigned", 4);
        add("ReturnPointWaveformLocation", "floating", 4);
        for (const char* t : {"Xt", "Yt", "Zt"}) add(t, "floating", 4);
    }
    return out;
}

// A closed ring around the box, as GeoJSON polygon coordinates.
json box_polygon(double x0, double y0, double x1, double y1) {
    return {{"type", "Polygon"}, {"coordinates", {{{x0, y0}, {x1, y0}, {x1, y1}, {x0, y1}, {x0, y0}}}}};
}

std::string utc_date(int year, int day_of_year) {
    std::tm t{};
    t.tm_year = year - 1900, t.tm_mon = 0, t.tm_mday = day_of_year;  // timegm normalises the day
    const std::time_t when = timegm(&t);
    std::tm n{};
    gmtime_r(&when, &n);
    char text[32];
    std::snprintf(text, sizeof text, "%04d-%02d-%02dT00:00:00Z", n.tm_year + 1900, n.tm_mon + 1, n.tm_mday);
    return text;
}

std::string utc_now() {
    const std::time_t now = std::time(nullptr);
    std::tm n{};
    gmtime_r(&now, &n);
    char text[32];
    std::strftime(text, sizeof text, "%Y-%m-%dT%H:%M:%SZ", &n);
    return text;
}

// datetime: the header's creation day; when it has none, null between 1970 and now (STAC's rule).
void add_dates(const las::Header& h, ordered_json& props) {
    if (h.creation_year >= 1970 && h.creation_day >= 1 && h.creation_day <= 366) {
        props["datetime"] = utc_date(h.creation_year, h.creation_day);
        return;
    }
    props["datetime"] = nullptr;
    props["start_datetime"] = "1970-01-01T00:00:00Z";
    props["end_datetime"] = utc_now();
}

// The asset href: a URL as it is, a local file relative to the catalog's folder ("./name").
std::string href_of(const std::string& path, const fs::path& catalog_folder) {
    if (net::is_url(path)) return path;
    const fs::path relative = fs::absolute(path).lexically_proximate(catalog_folder);
    const std::string r = relative.generic_string();
    return relative.is_absolute() || r.rfind("../", 0) == 0 ? r : "./" + r;
}

std::string unique_id(const std::string& path, std::set<std::string>& used) {
    const std::string plain = net::is_url(path) ? path.substr(0, path.find_first_of("?#")) : path;
    std::string stem = fs::path(plain).filename().string();
    for (const char* ext : {".copc.laz", ".laz", ".las"}) {
        const std::string e = ext;
        if (stem.size() > e.size() && stem.compare(stem.size() - e.size(), e.size(), e) == 0) {
            stem.resize(stem.size() - e.size());
            break;
        }
    }
    std::string id = stem;
    for (int k = 2; !used.insert(id).second; ++k) id = stem + "-" + std::to_string(k);
    return id;
}

// The tile's CRS in `props`: proj:epsg when one EPSG code says all of it, else proj:wkt2 (a compound CRS,
// or one without a code). The projection extension takes one of them, and the VPC specification asks
// for WKT where a single code would lose the heights' part; 1.9 KB of WKT in every item would make a
// country's catalog hundreds of MB. False when PROJ does not know the CRS: the item then has none (the
// tile's own header still says it).
bool add_crs(const Tile& tile, ordered_json& props) {
    const std::string def = geo::crs_definition(tile.crs());
    std::string wkt;
    try {
        if (!def.empty()) wkt = geo::crs_info(def).wkt;
    } catch (const Error&) {
        return false;
    }
    if (wkt.empty()) return false;
    const auto epsg = tile.crs().epsg;
    if (epsg && def == "EPSG:" + std::to_string(*epsg)) {
        props["proj:epsg"] = *epsg;
    } else {
        props["proj:wkt2"] = wkt;
    }
    return true;
}

ordered_json item_json(const Tile& tile, const std::string& path, const std::string& id, const fs::path& folder,
                       bool& without_crs) {
    const las::Header& h = tile.header;
    ordered_json props;
    add_dates(h, props);
    props["pc:count"] = h.point_count;
    props["pc:type"] = "lidar";
    props["pc:encoding"] = tile.copc ? "application/vnd.laszip+copc" : tile.compressed() ? "laszip" : "binary";
    props["pc:schemas"] = point_schema(h.point_format);
    props["proj:bbox"] = {h.min[0], h.min[1], h.min[2], h.max[0], h.max[1], h.max[2]};
    // (no proj:geometry: it would be proj:bbox's rectangle again, which readers take instead)
    without_crs = !add_crs(tile, props);
    const auto ll = tile_lonlat_bounds(tile);
    ordered_json item;
    item["type"] = "Feature";
    item["stac_version"] = "1.0.0";
    item["stac_extensions"] = {kPointcloudExtension, kProjectionExtension};
    item["id"] = id;
    // GeoJSON wants WGS 84; a tile without a usable CRS keeps its own box (as PDAL wrench does).
    item["geometry"] = ll ? box_polygon(ll->west, ll->south, ll->east, ll->north)
                          : box_polygon(h.min[0], h.min[1], h.max[0], h.max[1]);
    item["bbox"] = ll ? json{ll->west, ll->south, h.min[2], ll->east, ll->north, h.max[2]}
                      : json{h.min[0], h.min[1], h.min[2], h.max[0], h.max[1], h.max[2]};
    item["properties"] = std::move(props);
    item["links"] = json::array();
    item["assets"] = {{"data",
                       {{"href", href_of(path, folder)},
                        {"roles", {"data"}},
                        {"type", tile.compressed() ? "application/vnd.laszip" : "application/vnd.las"}}}};
    return item;
}

}  // namespace

std::vector<std::string> catalog_paths(const Dataset& dataset, std::span<const TileSource> sources,
                                       const std::string& folder) {
    if (std::none_of(sources.begin(), sources.end(), [](const TileSource& s) { return !s.name.empty(); })) return {};
    std::vector<std::string> out;
    std::size_t i = 0;  // the tiles are the sources read, in order; a source's tiles are read or not together
    for (const auto& t : dataset.tiles) {
        while (i < sources.size() && sources[i].path != t.tile.path()) ++i;
        if (i == sources.size()) throw Error::in_stage("catalog", "internal: a tile of no source " + t.tile.path());
        out.push_back(sources[i].name.empty() ? t.tile.path() : (fs::path(folder) / sources[i].name).string());
        ++i;
    }
    return out;
}

namespace {

const std::string& tile_path(const Dataset& dataset, const CatalogWriteOptions& options, std::size_t i) {
    return options.paths.empty() ? dataset.tiles[i].tile.path() : options.paths.at(i);
}

}  // namespace

std::vector<std::string> catalog_ids(const Dataset& dataset, const CatalogWriteOptions& options) {
    std::set<std::string> used;
    std::vector<std::string> ids;
    for (std::size_t i = 0; i < dataset.tiles.size(); ++i) {
        ids.push_back(unique_id(tile_path(dataset, options, i), used));
    }
    return ids;
}

CatalogWriteResult write_catalog(const Dataset& dataset, const std::string& output,
                                 const CatalogWriteOptions& options) {
    const auto path_of = [&](std::size_t i) { return tile_path(dataset, options, i); };
    std::set<std::string> paths;
    for (std::size_t i = 0; i < dataset.tiles.size(); ++i) {
        if (!paths.insert(path_of(i)).second) {
            throw Error::in_stage("catalog", path_of(i) + " stands for several tiles (a virtual replica): a "
                                             "catalog names files, so write the replica's tiles first "
                                             "(synth replicate without --virtual)");
        }
    }
    const fs::path folder = fs::absolute(output).parent_path();
    CatalogWriteResult result;
    result.ids = catalog_ids(dataset, options);
    // One item a line, written as it is made: a country's catalog is never held whole, as text or as JSON.
    io::AtomicOutputFile out(output);
    const auto write = [&out](const std::string& text) {
        out.write(std::span(reinterpret_cast<const std::uint8_t*>(text.data()), text.size()));
    };
    // The sidecar's link before the items: a reader fetches the country's overview while it reads them.
    write("{\"type\":\"FeatureCollection\",");
    if (!options.overview.empty()) {
        const ordered_json links = {{{"rel", kOverviewRel}, {"href", href_of(options.overview, folder)},
                                     {"type", "application/vnd.laszip"},
                                     {"title", "overview sidecar: every tile's chunk points and metadata "
                                               "(lidarscout)"}}};
        write("\"links\":" + links.dump() + ",");
    }
    write("\"features\":[\n");
    for (std::size_t i = 0; i < dataset.tiles.size(); ++i) {
        bool without_crs = false;
        const auto item = item_json(dataset.tiles[i].tile, path_of(i), result.ids[i], folder, without_crs);
        write((i ? ",\n" : "") + item.dump());
        result.without_crs += without_crs;
        ++result.items;
    }
    write("\n]}\n");
    out.commit();
    return result;
}

}  // namespace lidarscout::dataset
