// `synth replicate`: grid layout (cell size, exact per-tile shifts), the byte copy with its
// header patch, and the replicate.json manifest.
#include "synth/replicate.hpp"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <limits>
#include <regex>
#include <set>

#include "core/error.hpp"
#include "core/thread_pool.hpp"
#include "dataset/file_search.hpp"
#include "dataset/virtual_replica.hpp"
#include "io/file.hpp"
#include "io/output_file.hpp"
#include "las/vlr.hpp"

namespace lidarscout::synth {
namespace fs = std::filesystem;

namespace {

// Header fields (LAS 1.0-1.5 share this layout): x/y offsets, then max x, min x, max y, min y.
constexpr std::uint64_t kOffsetXY = 155;
constexpr std::uint64_t kBoundsXY = 179;
constexpr std::uint64_t kMaxCells = 10'000'000;

void put_f64(std::uint8_t* out, double v) {
    static_assert(std::endian::native == std::endian::little, "LAS is little-endian");
    std::memcpy(out, &v, 8);
}

std::uint32_t parse_count(const std::string& digits, const std::string& text) {
    if (digits.size() > 7) throw Error("--grid " + text + ": too many cells");
    const auto n = static_cast<std::uint32_t>(std::stoul(digits));
    if (n == 0) throw Error("--grid " + text + ": each side needs at least one cell");
    return n;
}

fs::path normalised(const fs::path& path) {
    std::error_code ec;
    auto p = fs::weakly_canonical(fs::absolute(path), ec).lexically_normal();
    return p.has_filename() ? p : p.parent_path();
}

// True when `path` lies inside `dir` (or is `dir`).
bool is_inside(const fs::path& path, const fs::path& dir) {
    const auto rel = normalised(path).lexically_relative(normalised(dir));
    return !rel.empty() && *rel.begin() != "..";
}

void check_output_folder(const std::string& out_dir, const std::vector<std::string>& args,
                         const std::vector<std::string>& files) {
    std::error_code ec;
    if (fs::exists(out_dir, ec) && !fs::is_directory(out_dir, ec)) {
        throw Error(out_dir, std::nullopt, "the output exists and is not a folder");
    }
    for (const auto& a : args) {
        if (fs::is_directory(a, ec) && is_inside(out_dir, a) && is_inside(a, out_dir)) {
            throw Error(out_dir, std::nullopt, "refusing to write into a source folder");
        }
    }
    for (const auto& f : files) {
        if (is_inside(f, out_dir)) {
            throw Error(out_dir, std::nullopt, "refusing to write into a folder that holds a source (" + f + ")");
        }
    }
}

// Shifts are whole units when the scale divides one unit (0.01, 0.001, ...), else whole
// multiples of the scale: either way the stored integers stay exact.
double shift_quantum(double scale) {
    const double steps = std::round(1.0 / scale);
    return (steps >= 1 && std::abs(steps * scale - 1.0) < 1e-9) ? 1.0 : std::abs(scale);
}

// Reads one source; nullopt (and a warning) when it cannot serve as a replica source.
std::optional<ReplicaSource> read_source(const std::string& path, Diagnostics& warnings) {
    ReplicaSource s;
    s.path = path;
    try {
        const auto file = io::File::open(path);
        s.tile = dataset::read_tile(file);
    } catch (const Error& e) {
        warnings.warn(std::string("skipping ") + e.what());
        return std::nullopt;
    }
    const auto& h = s.tile.header;
    if (s.tile.crs().geographic) {
        warnings.warn("skipping " + path + ": geographic coordinates (degrees) cannot be laid on a metre grid");
        return std::nullopt;
    }
    if (!std::isfinite(h.min[0] + h.min[1] + h.max[0] + h.max[1])) {
        warnings.warn("skipping " + path + ": its x/y bounds are not finite numbers");
        return std::nullopt;
    }
    s.to_metres = s.tile.crs().horizontal_to_metres;
    s.unit = las::unit_name(s.tile.crs().horizontal_unit);
    if (!std::isfinite(s.to_metres) || s.to_metres <= 0) {
        warnings.warn(path + ": horizontal unit unknown; taken as metres for the grid");
        s.to_metres = 1.0;
    }
    const double width = std::max(0.0, std::max(h.max[0] - h.min[0], h.max[1] - h.min[1]));
    s.footprint_metres = width * s.to_metres;
    s.quantum = {shift_quantum(h.scale[0]), shift_quantum(h.scale[1])};
    return s;
}

// The next round number at or above `metres`: 1-2 significant digits (1524 -> 1600).
double round_up(double metres) {
    if (!(metres > 1.0)) return 1.0;
    const double step = std::max(1.0, std::pow(10.0, std::floor(std::log10(metres)) - 1));
    return std::ceil(metres / step) * step;
}

// A cell holds any source with room for the shift's rounding (one quantum).
double cell_size(const std::vector<ReplicaSource>& sources) {
    double need = 0;
    for (const auto& s : sources) {
        need = std::max(need, s.footprint_metres + std::max(s.quantum[0], s.quantum[1]) * s.to_metres);
    }
    return round_up(need);
}

// The shift (in the source's units) that puts its min corner at the cell's corner, rounded up
// to a whole quantum so the stored integers stay exact.
double axis_shift(const ReplicaSource& s, int axis, double corner_metres) {
    const double want = (corner_metres - s.tile.header.min[axis] * s.to_metres) / s.to_metres;
    return std::ceil(want / s.quantum[axis] - 1e-6) * s.quantum[axis] + 0.0;  // + 0.0: no -0
}

std::string replica_name(const std::string& source, std::uint32_t gx, std::uint32_t gy) {
    const fs::path p(source);
    return p.stem().string() + "_x" + std::to_string(gx) + "_y" + std::to_string(gy) + p.extension().string();
}

void lay_out(ReplicatePlan& plan) {
    const auto& first = plan.sources.front();
    plan.anchor_metres = {first.tile.header.min[0] * first.to_metres, first.tile.header.min[1] * first.to_metres};
    plan.cell_metres = cell_size(plan.sources);
    const auto n = plan.sources.size();
    for (std::uint32_t gy = 0; gy < plan.grid.ny; ++gy) {
        for (std::uint32_t gx = 0; gx < plan.grid.nx; ++gx) {
            ReplicaTile t;
            t.gx = gx;
            t.gy = gy;
            t.source = (gx + static_cast<std::uint64_t>(gy) * plan.grid.nx) % n;
            const auto& s = plan.sources[t.source];
            t.shift = {axis_shift(s, 0, plan.anchor_metres[0] + gx * plan.cell_metres),
                       axis_shift(s, 1, plan.anchor_metres[1] + gy * plan.cell_metres)};
            t.path = (fs::path(plan.out_dir) / replica_name(s.path, gx, gy)).string();
            plan.total_bytes += s.tile.file_size();
            plan.total_points += s.tile.header.point_count;
            plan.tiles.push_back(std::move(t));
        }
    }
}

// Other LAS/LAZ files already in the output folder stay there and would join the dataset.
void warn_stale_outputs(ReplicatePlan& plan) {
    std::error_code ec;
    if (!fs::is_directory(plan.out_dir, ec)) return;
    std::set<std::string> ours;
    for (const auto& t : plan.tiles) ours.insert(fs::path(t.path).filename().string());
    std::size_t stale = 0;
    for (const auto& e : fs::directory_iterator(plan.out_dir, ec)) {
        const auto name = e.path().filename().string();
        if (dataset::has_point_cloud_extension(name) && !ours.count(name)) ++stale;
    }
    if (stale > 0) {
        plan.warnings.warn(plan.out_dir + ": already holds " + std::to_string(stale) +
                                " other LAS/LAZ files that this run does not replace");
    }
}

// Writes the header's x/y offsets and bounds of `shifted` (dataset::shift_tile moved them).
void patch_header(io::AtomicOutputFile& out, const las::Header& h) {
    std::uint8_t offsets[16], bounds[32];
    put_f64(offsets, h.offset[0]);
    put_f64(offsets + 8, h.offset[1]);
    put_f64(bounds, h.max[0]);
    put_f64(bounds + 8, h.min[0]);
    put_f64(bounds + 16, h.max[1]);
    put_f64(bounds + 24, h.min[1]);
    out.write_at(kOffsetXY, offsets);
    out.write_at(kBoundsXY, bounds);
}

// The COPC info VLR holds the octree centre in absolute coordinates: it moves with the points
// (the hierarchy holds file offsets, which the copy keeps).
void patch_copc_centre(io::AtomicOutputFile& out, const dataset::Tile& shifted) {
    const auto* vlr = las::find_vlr(shifted.vlrs(), "copc", 1);
    if (!vlr) throw Error(shifted.path(), std::nullopt, "COPC info VLR not found");
    std::uint8_t centre[16];
    put_f64(centre, shifted.copc->center[0]);
    put_f64(centre + 8, shifted.copc->center[1]);
    out.write_at(vlr->data_offset, centre);
}

nlohmann::ordered_json manifest(const ReplicatePlan& plan, bool virtual_tiles) {
    nlohmann::ordered_json sources = nlohmann::ordered_json::array(), tiles = nlohmann::ordered_json::array();
    for (const auto& s : plan.sources) {
        sources.push_back({{"path", fs::absolute(s.path).string()}, {"unit", s.unit}, {"to_metres", s.to_metres},
                           {"footprint_metres", s.footprint_metres}, {"points", s.tile.header.point_count},
                           {"bytes", s.tile.file_size()}, {"copc", s.tile.copc.has_value()}});
    }
    for (const auto& t : plan.tiles) {
        tiles.push_back({{"file", fs::path(t.path).filename().string()}, {"gx", t.gx}, {"gy", t.gy},
                         {"source", t.source}, {"shift", {t.shift[0], t.shift[1]}}});
    }
    // "tool" and "virtual" first: dataset::is_virtual_replica reads only the head of the file.
    return {{"tool", dataset::kReplicaTool},
            {"virtual", virtual_tiles},
            {"purpose", std::string("benchmark data, not a data product: real tiles ") +
                            (virtual_tiles ? "placed (virtually, nothing copied) " : "copied ") +
                            "onto a grid, only the header's x/y offsets and bounds moved; points repeat and "
                            "neighbouring tiles do not join"},
            {"grid", {{"nx", plan.grid.nx}, {"ny", plan.grid.ny}, {"cell_metres", plan.cell_metres},
                      {"anchor_metres", {plan.anchor_metres[0], plan.anchor_metres[1]}}}},
            {"shift_units", "each source's own x/y units (see sources[].unit)"},
            {"total_tiles", plan.tiles.size()}, {"total_bytes", plan.total_bytes},
            {"total_points", plan.total_points}, {"sources", sources}, {"tiles", tiles}};
}

void write_manifest(const ReplicatePlan& plan, bool virtual_tiles) {
    const auto text = manifest(plan, virtual_tiles).dump(1) + "\n";
    io::AtomicOutputFile out((fs::path(plan.out_dir) / kManifestName).string());
    out.write({reinterpret_cast<const std::uint8_t*>(text.data()), text.size()});
    out.commit();
}

}  // namespace

GridSize parse_grid(const std::string& text) {
    static const std::regex form(R"(\s*([0-9]+)\s*[xX]\s*([0-9]+)\s*)");
    std::smatch m;
    if (!std::regex_match(text, m, form)) throw Error("--grid " + text + ": expected NXxNY, e.g. 45x45");
    GridSize g{parse_count(m[1].str(), text), parse_count(m[2].str(), text)};
    if (static_cast<std::uint64_t>(g.nx) * g.ny > kMaxCells) {
        throw Error("--grid " + text + ": more than " + std::to_string(kMaxCells) + " cells");
    }
    return g;
}

ReplicatePlan plan_replicas(const std::vector<std::string>& sources, const std::string& out_dir, GridSize grid) {
    if (grid.nx == 0 || grid.ny == 0) throw Error("the grid needs at least one cell on each side");
    if (out_dir.empty()) throw Error("no output folder given");
    auto found = dataset::find_point_cloud_files(sources);
    if (!found.errors.empty()) throw Error(found.errors.front().error);
    check_output_folder(out_dir, sources, found.files);
    ReplicatePlan plan;
    plan.out_dir = out_dir;
    plan.grid = grid;
    for (const auto& f : found.files) {
        if (auto s = read_source(f, plan.warnings)) plan.sources.push_back(std::move(*s));
    }
    if (plan.sources.empty()) throw Error("no readable LAS/LAZ source tile among the sources given");
    lay_out(plan);
    warn_stale_outputs(plan);
    return plan;
}

void write_replica(const io::File& source, const dataset::Tile& tile, const std::string& target,
                   std::array<double, 2> shift) {
    io::AtomicOutputFile out(target, source.path());
    out.copy_from(source, 0, source.size());
    dataset::Tile shifted = tile;  // what a virtual replica shifts in memory, written into the copy
    dataset::shift_tile(shifted, shift);
    patch_header(out, shifted.header);
    if (shifted.copc) patch_copc_centre(out, shifted);
    out.commit();
}

void write_replicas(const ReplicatePlan& plan, ThreadPool& pool, const std::function<void(std::uint64_t)>& on_bytes) {
    std::error_code ec;
    fs::create_directories(plan.out_dir, ec);
    if (ec) throw Error(plan.out_dir, std::nullopt, "cannot create the output folder: " + ec.message());
    std::vector<io::File> files;
    files.reserve(plan.sources.size());
    for (const auto& s : plan.sources) files.push_back(io::File::open(s.path));
    pool.for_each(plan.tiles.size(), [&](std::size_t i) {
        const auto& t = plan.tiles[i];
        const auto& file = files[t.source];
        if (file.size() != plan.sources[t.source].tile.file_size()) {
            throw Error(file.path(), std::nullopt, "the source changed size while being replicated");
        }
        write_replica(file, plan.sources[t.source].tile, t.path, t.shift);
        if (on_bytes) on_bytes(file.size());
    });
    write_manifest(plan, false);
}

void write_virtual_replica(const ReplicatePlan& plan) {
    std::error_code ec;
    fs::create_directories(plan.out_dir, ec);
    if (ec) throw Error(plan.out_dir, std::nullopt, "cannot create the output folder: " + ec.message());
    write_manifest(plan, true);
}

}  // namespace lidarscout::synth
