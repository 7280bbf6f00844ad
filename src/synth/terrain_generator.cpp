// generate_terrain: validates the options, checks the output folder, then writes every tile
// in parallel (scan_tile -> records -> LasWriter) and finally the manifest.
#include "synth/terrain_generator.hpp"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <limits>
#include <set>

#include "core/error.hpp"
#include "core/random.hpp"
#include "core/thread_pool.hpp"
#include "laz/laz.hpp"
#include "io/file.hpp"
#include "io/output_file.hpp"
#include "las/header_writer.hpp"
#include "las/point_format.hpp"
#include "synth/flight_plan.hpp"
#include "synth/terrain_model.hpp"
#include "synth/terrain_scan.hpp"

namespace lidarscout::synth {
namespace fs = std::filesystem;
namespace {

constexpr double kMaxKm = 200.0;
constexpr double kMaxDensity = 1000.0;
constexpr std::uint8_t kPointFormat = 7;
constexpr double kScale = 0.01;
constexpr std::size_t kBatchChunks = 4;  // chunks handed to the writer at a time
enum Stream : std::uint64_t { kGuid = 801 };

las::Header demo_header(const TerrainOptions& o, const Area& area) {
    las::Header h;
    h.version_major = 1;
    h.version_minor = 4;
    h.header_size = las::standard_header_size(1, 4);
    h.global_encoding = 1 | 16;  // adjusted standard GPS time; the CRS is WKT
    h.system_identifier = "lidarscout synthetic survey";
    h.generating_software = kTerrainSoftware;
    h.creation_day = 165;  // the survey's date: 2023-06-14
    h.creation_year = 2023;
    const std::uint64_t a = hash_of(o.seed, kGuid, 0), b = hash_of(o.seed, kGuid, 1);
    for (int i = 0; i < 8; ++i) {
        h.project_guid[i] = static_cast<std::uint8_t>(a >> (8 * i));
        h.project_guid[8 + i] = static_cast<std::uint8_t>(b >> (8 * i));
    }
    h.point_format = kPointFormat;
    h.record_length = las::point_format_info(kPointFormat).size;
    h.scale = {kScale, kScale, kScale};
    h.offset = {area.x0, area.y0, 0.0};
    return h;
}

las::Vlr wkt_vlr() {
    las::Vlr v;
    v.user_id = "LASF_Projection";
    v.record_id = 2112;
    v.description = "OGC WKT";
    const std::string& wkt = terrain_wkt();
    v.data.assign(wkt.begin(), wkt.end());
    v.data.push_back(0);
    return v;
}

// Encodes a tile's points into records, hands them to the writer in batches of whole chunks,
// and gathers what the header reports (bounds, points by return).
class TileRecords {
public:
    TileRecords(laz::LasWriter& writer, std::uint32_t chunk_size)
        : writer_(writer),
          format_(las::point_format_info(kPointFormat)),
          batch_(std::size_t{chunk_size} * kBatchChunks) {
        buffer_.reserve(batch_ * format_.size);
    }

    void add(const las::Point& p) {
        const std::size_t at = buffer_.size();
        buffer_.resize(at + format_.size);
        las::encode_point(p, format_, std::span(buffer_).subspan(at, format_.size));
        for (int a = 0; a < 3; ++a) {
            const std::int32_t v = a == 0 ? p.X : a == 1 ? p.Y : p.Z;
            min_[a] = std::min(min_[a], v);
            max_[a] = std::max(max_[a], v);
        }
        ++by_return_[p.return_number - 1];
        if (buffer_.size() >= batch_ * format_.size) flush();
    }

    void flush() {
        writer_.add(buffer_);
        buffer_.clear();
    }

    // Fills the header's bounds and per-return counts.
    void describe(las::Header& h) const {
        const bool empty = writer_.points() == 0;
        for (int a = 0; a < 3; ++a) {
            h.min[a] = empty ? h.offset[a] : min_[a] * h.scale[a] + h.offset[a];
            h.max[a] = empty ? h.offset[a] : max_[a] * h.scale[a] + h.offset[a];
        }
        h.points_by_return.fill(0);
        std::copy(by_return_.begin(), by_return_.end(), h.points_by_return.begin());
    }

private:
    laz::LasWriter& writer_;
    const las::PointFormatInfo& format_;
    std::size_t batch_;
    std::vector<std::uint8_t> buffer_;
    std::array<std::int32_t, 3> min_{std::numeric_limits<std::int32_t>::max(), std::numeric_limits<std::int32_t>::max(),
                                     std::numeric_limits<std::int32_t>::max()};
    std::array<std::int32_t, 3> max_{std::numeric_limits<std::int32_t>::min(), std::numeric_limits<std::int32_t>::min(),
                                     std::numeric_limits<std::int32_t>::min()};
    std::array<std::uint64_t, 3> by_return_{};  // the scan gives at most three returns
};

TerrainTile write_tile(const TerrainModel& model, const FlightPlan& plan, const TileRect& rect, const std::string& path,
                       const TerrainOptions& options, ThreadPool& pool) {
    const las::Header header = demo_header(options, model.area());
    laz::LasWriterOptions write;
    write.chunk_size = options.chunk_size;
    laz::LasWriter writer(path, header, {wkt_vlr()}, write, pool);
    TileRecords records(writer, options.chunk_size);
    Quantisation q;
    q.scale = kScale;
    q.offset = header.offset;
    scan_tile(model, plan, rect, q, [&](const las::Point& p) { records.add(p); });
    records.flush();
    records.describe(writer.header());
    const auto written = writer.finish();
    return {path, rect.ix, rect.iy, written.points, written.chunks, written.bytes_written};
}

bool is_point_file(const fs::path& p) {
    std::string ext = p.extension().string();
    for (auto& c : ext) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    return ext == ".las" || ext == ".laz";
}

bool is_demo_tile(const fs::path& p) {
    try {
        const auto file = io::File::open(p.string());
        return las::read_header(file).generating_software == kTerrainSoftware;
    } catch (const Error&) {
        return false;
    }
}

// Creates the folder and makes sure the run only replaces earlier demo tiles of its own names.
void prepare_folder(const std::string& dir, const std::set<std::string>& names) {
    std::error_code ec;
    fs::create_directories(dir, ec);
    if (ec || !fs::is_directory(dir)) {
        throw Error(dir, std::nullopt, "cannot create the output folder" + (ec ? ": " + ec.message() : std::string()));
    }
    for (const auto& entry : fs::directory_iterator(dir)) {
        if (!is_point_file(entry.path())) continue;
        const std::string name = entry.path().filename().string();
        if (!names.count(name)) {
            throw Error(dir, std::nullopt, "the folder holds " + name +
                                               ", which this demo would not write; use an empty folder (or remove it)");
        }
        if (!is_demo_tile(entry.path())) {
            throw Error(entry.path().string(), std::nullopt,
                        "refusing to overwrite a file that is not a lidarscout demo tile");
        }
    }
    fs::remove(fs::path(dir) / kTerrainManifest, ec);  // the demo is incomplete until the end
}

std::string number(double v) {
    char buf[64];
    std::snprintf(buf, sizeof buf, "%.10g", v);
    return buf;
}

void write_manifest(const std::string& dir, const TerrainOptions& o, const TerrainResult& r) {
    std::string s = "{\n  \"generator\": \"" + std::string(kTerrainSoftware) +
                    "\",\n  \"seed\": " + std::to_string(o.seed) + ",\n  \"km\": " + number(r.area.size() / 1000.0) +
                    ",\n  \"density\": " + number(o.density) + ",\n  \"origin\": [" + number(r.area.x0) + ", " +
                    number(r.area.y0) + "]" + ",\n  \"tiles\": " + std::to_string(r.tiles.size()) +
                    ",\n  \"points\": " + std::to_string(r.points) + ",\n  \"bytes\": " + std::to_string(r.bytes) +
                    ",\n  \"files\": [";
    for (std::size_t i = 0; i < r.tiles.size(); ++i) {
        s += (i ? ", \"" : "\"") + fs::path(r.tiles[i].path).filename().string() + "\"";
    }
    s += "]\n}\n";
    io::AtomicOutputFile out((fs::path(dir) / kTerrainManifest).string());
    out.write(std::span(reinterpret_cast<const std::uint8_t*>(s.data()), s.size()));
    out.commit();
}

}  // namespace

Area terrain_area(const TerrainOptions& o) {
    if (!(o.km > 0 && o.km <= kMaxKm)) {
        throw Error("the demo's size must be more than 0 and at most " + number(kMaxKm) + " km (got " + number(o.km) +
                    ")");
    }
    if (!(o.density > 0 && o.density <= kMaxDensity)) {
        throw Error("the demo's density must be more than 0 and at most " + number(kMaxDensity) +
                    " points per square metre (got " + number(o.density) + ")");
    }
    if (o.chunk_size == 0) throw Error("chunk size must be positive");
    Area area;
    area.tiles = static_cast<std::uint32_t>(std::ceil(o.km * 1000.0 / kTileSize - 1e-9));
    return area;
}

std::string terrain_tile_name(std::uint32_t ix, std::uint32_t iy) {
    char buf[64];
    std::snprintf(buf, sizeof buf, "demo_%03u_%03u.laz", ix, iy);
    return buf;
}

const std::string& terrain_wkt() {
    static const std::string wkt =
        "COMPD_CS[\"ETRS89 / UTM zone 32N + DHHN2016 height\","
        "PROJCS[\"ETRS89 / UTM zone 32N\","
        "GEOGCS[\"ETRS89\",DATUM[\"European_Terrestrial_Reference_System_1989\","
        "SPHEROID[\"GRS 1980\",6378137,298.257222101,AUTHORITY[\"EPSG\",\"7019\"]],AUTHORITY[\"EPSG\",\"6258\"]],"
        "PRIMEM[\"Greenwich\",0,AUTHORITY[\"EPSG\",\"8901\"]],"
        "UNIT[\"degree\",0.0174532925199433,AUTHORITY[\"EPSG\",\"9122\"]],AUTHORITY[\"EPSG\",\"4258\"]],"
        "PROJECTION[\"Transverse_Mercator\"],PARAMETER[\"latitude_of_origin\",0],PARAMETER[\"central_meridian\",9],"
        "PARAMETER[\"scale_factor\",0.9996],PARAMETER[\"false_easting\",500000],PARAMETER[\"false_northing\",0],"
        "UNIT[\"metre\",1,AUTHORITY[\"EPSG\",\"9001\"]],AXIS[\"Easting\",EAST],AXIS[\"Northing\",NORTH],"
        "AUTHORITY[\"EPSG\",\"25832\"]],"
        "VERT_CS[\"DHHN2016 height\",VERT_DATUM[\"Deutsches Haupthoehennetz 2016\",2005,AUTHORITY[\"EPSG\",\"1170\"]],"
        "UNIT[\"metre\",1,AUTHORITY[\"EPSG\",\"9001\"]],AXIS[\"Gravity-related "
        "height\",UP],AUTHORITY[\"EPSG\",\"7837\"]]]";
    return wkt;
}

TerrainResult generate_terrain(const TerrainOptions& options, const std::string& out_dir, ThreadPool& pool,
                               const TerrainProgressFn& progress) {
    TerrainResult result;
    result.area = terrain_area(options);
    const Area& area = result.area;
    std::vector<TileRect> rects;
    std::set<std::string> names;
    for (std::uint32_t iy = 0; iy < area.tiles; ++iy) {
        for (std::uint32_t ix = 0; ix < area.tiles; ++ix) {
            rects.push_back(tile_rect(area, ix, iy));
            names.insert(terrain_tile_name(ix, iy));
        }
    }
    prepare_folder(out_dir, names);

    const TerrainModel model(options.seed, area);
    const FlightPlan plan = plan_flight(options.seed, area, options.density / kReturnsPerPulse);
    result.tiles.resize(rects.size());
    pool.for_each(rects.size(), [&](std::size_t t) {
        const auto path = (fs::path(out_dir) / terrain_tile_name(rects[t].ix, rects[t].iy)).string();
        result.tiles[t] = write_tile(model, plan, rects[t], path, options, pool);
        if (progress) progress(result.tiles[t]);
    });
    for (const auto& t : result.tiles) {
        result.points += t.points;
        result.bytes += t.bytes;
    }
    write_manifest(out_dir, options, result);
    return result;
}

}  // namespace lidarscout::synth
