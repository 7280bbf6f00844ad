// `lidarscout info PATH... [--json] [--chunks]`: what each LAS/LAZ file holds (header, VLRs,
// CRS and units, LAZ layout, COPC), optionally its chunk table and chunk points; a summary
// for folders. A file that cannot be read gets one line; the others are still reported.
#include <CLI/CLI.hpp>
#include <fmt/format.h>

#include <algorithm>
#include <cstdio>
#include <limits>
#include <optional>

#include "cli/commands.hpp"
#include "cli/json_output.hpp"
#include "cli/diagnostic_output.hpp"
#include "cli/io_options.hpp"
#include "cli/progress.hpp"
#include "cli/tile_json.hpp"
#include "cli/thread_options.hpp"
#include "core/text.hpp"
#include "core/error.hpp"
#include "core/sha256.hpp"
#include "core/thread_pool.hpp"
#include "dataset/chunk_points.hpp"
#include "dataset/file_search.hpp"
#include "dataset/stac_catalog.hpp"
#include "dataset/virtual_replica.hpp"
#include "dataset/point_reader.hpp"
#include "dataset/tile.hpp"
#include "io/file.hpp"

namespace lidarscout::cli {
namespace {

struct InfoOptions {
    std::vector<std::string> paths;
    bool json = false;
    bool chunks = false;
    bool checksum = false;
    unsigned threads = 0;
};

struct FileReport {
    std::string path;
    std::optional<dataset::Tile> tile;
    std::vector<dataset::ChunkPoint> chunk_points;
    std::uint64_t chunk_point_count = 0;
    std::string points_sha256;  // with --checksum
    std::string error;
    std::string catalog_disagreement;  // how the header disagrees with the tile's catalog item ("" when not)
};


// SHA-256 over the raw bytes of every point record, in file order, after decoding.
std::string points_checksum(const io::File& file, const dataset::Tile& tile) {
    Sha256 sha;
    dataset::for_each_record_batch(file, tile, ThreadPool::shared(),
                                   [&](std::uint64_t, std::span<const std::uint8_t> records) { sha.update(records); });
    return sha.hex_digest();
}

FileReport inspect(const dataset::TileSource& source, const InfoOptions& opt) {
    // a URL without its credentials; a virtual replica's tile by its name and source
    const std::string path = io::display_path(source.path);
    FileReport r{source.name.empty() ? path : source.name + " (" + path + ", shifted)", std::nullopt, {}, 0, {}, {}};
    try {
        auto file = io::File::open(source.path);
        r.tile = dataset::read_tile(file);
        if (source.shift) dataset::shift_tile(*r.tile, *source.shift);
        r.chunk_point_count = dataset::chunk_point_count(*r.tile);
        if (opt.chunks) r.chunk_points = dataset::read_chunk_points(file, *r.tile);
        if (opt.checksum) r.points_sha256 = points_checksum(file, *r.tile);
    } catch (const Error& e) {
        r.tile.reset();
        r.error = e.file().empty() ? r.path + ": " + e.what() : e.what();
    } catch (const std::bad_alloc&) {
        r.tile.reset();
        r.error = r.path + ": out of memory while reading the file";
    }
    if (source.item && !r.tile) r.error += " (" + dataset::item_name(*source.item) + ")";
    if (source.item && r.tile) r.catalog_disagreement = dataset::item_disagreement(*source.item, *r.tile);
    return r;
}

std::string thousands(std::uint64_t v) {
    const std::string digits = std::to_string(v);
    std::string out;
    out.reserve(digits.size() + digits.size() / 3);
    for (std::size_t i = 0; i < digits.size(); ++i) {
        if (i > 0 && (digits.size() - i) % 3 == 0) out += ',';
        out += digits[i];
    }
    return out;
}

std::string crs_text(const las::Crs& c) {
    if (c.source == "none") return "none";
    const std::string code = c.epsg ? fmt::format("EPSG:{}", *c.epsg) : "no EPSG code";
    const std::string name = c.name.empty() ? "" : fmt::format(" ({})", c.name);
    return fmt::format("{}{}, horizontal unit {}, vertical unit {}", code, name, las::unit_name(c.horizontal_unit),
                       las::unit_name(c.vertical_unit));
}

void print_laz_text(const dataset::Tile& t) {
    const auto& z = *t.laz();
    static const char* kCompressors[] = {"none", "point-wise", "point-wise chunked", "layered chunked"};
    std::string items;
    for (const auto& it : z.items) {
        items += fmt::format("{}{} v{} ({} B)", items.empty() ? "" : ", ", las::item_type_name(it.type), it.version,
                             it.size);
    }
    std::printf("  LAZ: compressor %u (%s), chunk size %s, items %s\n", z.compressor,
                z.compressor < 4 ? kCompressors[z.compressor] : "?",
                z.variable_chunks() ? "variable" : thousands(z.chunk_size).c_str(), items.c_str());
    if (t.chunks()) std::printf("  chunks: %s\n", thousands(t.chunks()->size()).c_str());
}

void print_chunks_text(const FileReport& r) {
    const auto& t = *r.tile;
    if (t.chunks()) {
        std::printf("  chunk table (%s entries):\n", thousands(t.chunks()->size()).c_str());
        for (std::size_t i = 0; i < t.chunks()->size(); ++i) {
            const auto& c = (*t.chunks())[i];
            std::printf("    %6zu  first %12llu  points %8llu  offset %12llu  bytes %10llu\n", i,
                        (unsigned long long)c.first_point, (unsigned long long)c.point_count,
                        (unsigned long long)c.byte_offset, (unsigned long long)c.byte_size);
        }
    }
    std::printf("  chunk points (%zu):\n", r.chunk_points.size());
    for (const auto& cp : r.chunk_points) {
        const auto& p = cp.point;
        std::printf("    #%-12llu %.3f %.3f %.3f  intensity %u  class %u\n", (unsigned long long)cp.index, p.x, p.y,
                    p.z, p.intensity, p.classification);
    }
}

void print_text(const FileReport& r, bool chunks) {
    if (!r.tile) return;  // errors go to stderr
    const auto& t = *r.tile;
    const auto& h = t.header;
    std::printf("%s\n", display_text(r.path).c_str());
    std::printf("  LAS %s, point format %u (%u bytes/record), %s points, %s, %s bytes\n", h.version_string().c_str(),
                h.point_format, h.record_length, thousands(h.point_count).c_str(),
                t.compressed() ? "LAZ" : "uncompressed", thousands(t.file_size()).c_str());
    std::printf("  software '%s', system '%s', created day %u of %u\n", display_text(h.generating_software).c_str(),
                display_text(h.system_identifier).c_str(), h.creation_day, h.creation_year);
    std::printf("  scale %g %g %g, offset %.3f %.3f %.3f\n", h.scale[0], h.scale[1], h.scale[2], h.offset[0],
                h.offset[1], h.offset[2]);
    std::printf("  bounds min %.3f %.3f %.3f, max %.3f %.3f %.3f\n", h.min[0], h.min[1], h.min[2], h.max[0], h.max[1],
                h.max[2]);
    for (const auto& w : t.warnings()) std::printf("  %s: %s\n", level_name(w.level), display_text(w.message).c_str());
    std::printf("  CRS: %s\n", display_text(crs_text(t.crs())).c_str());
    for (const auto& w : t.crs().warnings) {
        std::printf("  CRS %s: %s\n", level_name(w.level), display_text(w.message).c_str());
    }
    if (const auto ll = dataset::tile_lonlat_bounds(t)) {
        std::printf("  lon/lat: %.6f .. %.6f, %.6f .. %.6f (WGS 84)\n", ll->west, ll->east, ll->south, ll->north);
    }
    for (const auto* list : {&t.vlrs(), &t.evlrs()}) {
        for (const auto& v : *list) {
            std::printf("  %s '%s' %u: %s bytes%s%s\n", v.extended ? "EVLR" : "VLR", display_text(v.user_id).c_str(),
                        v.record_id, thousands(v.data_size).c_str(), v.description.empty() ? "" : ", ",
                        display_text(v.description).c_str());
        }
    }
    if (t.laz()) print_laz_text(t);
    if (t.copc) std::printf("  COPC: halfsize %g, spacing %g\n", t.copc->halfsize, t.copc->spacing);
    std::printf("  chunk points: %s\n", thousands(r.chunk_point_count).c_str());
    if (!r.points_sha256.empty()) std::printf("  points_sha256: %s\n", r.points_sha256.c_str());
    if (chunks) print_chunks_text(r);
}

void print_summary(const std::vector<FileReport>& reports) {
    std::uint64_t points = 0, chunk_points = 0, ok = 0;
    std::array<double, 3> lo{}, hi{};
    lo.fill(std::numeric_limits<double>::infinity());
    hi.fill(-std::numeric_limits<double>::infinity());
    for (const auto& r : reports) {
        if (!r.tile) continue;
        ++ok;
        points += r.tile->header.point_count;
        chunk_points += r.chunk_point_count;
        for (int i = 0; i < 3; ++i) {
            lo[i] = std::min(lo[i], r.tile->header.min[i]);
            hi[i] = std::max(hi[i], r.tile->header.max[i]);
        }
    }
    std::printf("dataset: %s files (%s failed), %s points, %s chunk points\n", thousands(reports.size()).c_str(),
                thousands(reports.size() - ok).c_str(), thousands(points).c_str(), thousands(chunk_points).c_str());
    if (ok) {
        std::printf("  bounds min %.3f %.3f %.3f, max %.3f %.3f %.3f (file coordinates)\n", lo[0], lo[1], lo[2], hi[0],
                    hi[1], hi[2]);
    }
}

nlohmann::json report_json(const FileReport& r, bool chunks) {
    if (!r.tile) return failed_tile_json(r.path, r.error);
    auto j = tile_to_json(*r.tile);
    j["chunk_point_count"] = r.chunk_point_count;
    if (!r.catalog_disagreement.empty()) j["catalog_disagreement"] = display_text(r.catalog_disagreement);
    if (!r.points_sha256.empty()) j["points_sha256"] = r.points_sha256;
    if (chunks) {
        j["chunks"] = chunks_to_json(*r.tile);
        j["chunk_points"] = chunk_points_to_json(r.chunk_points, *r.tile);
    }
    return j;
}

int run_info(const InfoOptions& opt) {
    const auto found = dataset::find_tile_sources(opt.paths);
    std::vector<FileReport> reports(found.sources.size());
    {
        Progress progress("info", reports.size());
        if (opt.threads) ThreadPool::set_shared_threads(opt.threads);
        ThreadPool::shared().for_each(reports.size(), [&](std::size_t i) {
            reports[i] = inspect(found.sources[i], opt);
            progress.add();
        });
    }
    bool failed = !found.errors.empty();
    for (const auto& e : found.errors) std::fprintf(stderr, "lidarscout: %s\n", display_text(e.error).c_str());
    print_diagnostics(found.warnings);  // tiles named more than once (each is described once), catalog items
    for (const auto& r : reports) {
        if (!r.catalog_disagreement.empty()) {
            std::fprintf(stderr, "lidarscout: warning: %s\n", display_text(r.catalog_disagreement).c_str());
        }
        if (!r.tile) {
            failed = true;
            std::fprintf(stderr, "lidarscout: %s\n", display_text(r.error).c_str());
        }
    }
    if (opt.json) {
        nlohmann::json arr = nlohmann::json::array();
        for (const auto& e : found.errors) arr.push_back(failed_tile_json(e.path, e.error));
        for (const auto& r : reports) arr.push_back(report_json(r, opt.chunks));
        print_json_answer(arr);
    } else {
        for (const auto& r : reports) print_text(r, opt.chunks);
        if (reports.size() > 1) print_summary(reports);
    }
    return failed ? 1 : 0;
}

}  // namespace

void register_info_command(CLI::App& app, std::function<int()>& run) {
    auto opt = std::make_shared<InfoOptions>();
    auto* cmd = app.add_subcommand("info", "Describe LAS/LAZ files: header, VLRs, CRS and units, LAZ layout, chunks");
    add_inputs(*cmd, "paths", opt->paths,
               "LAS/LAZ files, folders (searched recursively), tile lists, EPT datasets; or http(s) or s3:// URLs")
        ->required();
    cmd->add_flag("--json", opt->json, "Print one JSON array with an object per file");
    cmd->add_flag("--chunks", opt->chunks, "Add the LAZ chunk table and the chunk points");
    cmd->add_flag("--checksum", opt->checksum,
                  "Decode every point and add points_sha256: SHA-256 over the raw point records in file order");
    add_thread_option(*cmd, "--threads", opt->threads, "Threads for reading files (default: all cores)");
    cmd->callback([opt, &run] { run = [opt] { return run_info(*opt); }; });
}

}  // namespace lidarscout::cli
