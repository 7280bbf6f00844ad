// A served dataset: its chunk points loading in the background, and the API's bodies made from
// the grid by the viewer's own pieces.
#include "serve/survey.hpp"

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <filesystem>
#include <iterator>

#include "core/error.hpp"
#include "core/thread_pool.hpp"
#include "nn/heightmap_network.hpp"
#include "render/camera.hpp"
#include "render/colour_modes.hpp"
#include "serve/encoding.hpp"
#include "viewer/heightmap_builder.hpp"
#include "viewer/point_sets.hpp"
#include "viewer/scene.hpp"

namespace lidarscout::serve {
namespace {

std::atomic<std::uint64_t> next_generation{1};

nlohmann::json bounds_json(const dataset::Bounds& b, double xy, double z) {
    return {b.min_x / xy, b.min_y / xy, b.min_z / z, b.max_x / xy, b.max_y / xy, b.max_z / z};
}

std::string file_name(const std::string& path) {
    const std::size_t slash = path.find_last_of('/');
    return slash == std::string::npos ? path : path.substr(slash + 1);
}

std::int64_t decimetres(double metres) { return static_cast<std::int64_t>(std::llround(metres * 10.0)); }

}  // namespace

Survey::Survey(dataset::Dataset dataset, ResponseCache& cache, int decode_slots)
    : dataset_(std::move(dataset)), cache_(cache), decodes_(std::max(1, decode_slots)),
      generation_(next_generation++) {
    const auto [ox, oy] = dataset::patch_grid_origin(dataset_);
    grid_ = std::make_unique<PatchGrid>(ox, oy);
    footprints_ = viewer::tile_footprints(dataset_);
    loader_ = std::make_unique<dataset::ChunkPointLoader>(dataset_, *grid_);
    loader_->set_focus(dataset_.bounds_m.centre_x(), dataset_.bounds_m.centre_y());
    loader_->start();
}

Survey::~Survey() = default;  // the loader cancels and waits first (declared after the grid)

std::string Survey::info_json(std::size_t index) const {
    const auto& f = dataset_.frame;
    nlohmann::json j = {
        {"index", index},
        {"tiles", dataset_.tiles.size()},
        {"skipped", dataset_.skipped.size()},
        {"point_count", dataset_.point_count},
        {"chunk_point_count", dataset_.chunk_point_count},
        {"crs", f.crs.substr(0, 2000)},
        {"frame", {{"xy_to_metres", f.xy_to_metres}, {"z_to_metres", f.z_to_metres}, {"geographic", f.geographic}}},
        {"bounds", bounds_json(dataset_.bounds_m, f.xy_to_metres, f.z_to_metres)},
        {"bounds_m", bounds_json(dataset_.bounds_m, 1, 1)},
        {"origin_m", {grid_->origin_x(), grid_->origin_y()}},
        {"patch_size_m", grid_->patch_size()},
        {"uncoloured_grey", viewer::kUncolouredGrey},
        {"cnn", !model_path_.empty()},
        {"loading", {{"tiles_done", loader_->tiles_done()}, {"chunk_points", loader_->loaded()},
                     {"chunk_points_total", loader_->total()}, {"failed", loader_->failed()},
                     {"finished", loader_->finished()}}}};
    if (loader_->finished()) {
        j["has_rgb"] = has_rgb();
        std::lock_guard lock(mutex_);
        if (!intensity_range_) intensity_range_ = intensity_range();
        j["intensity_range"] = *intensity_range_;
    }
    return j.dump();
}

bool Survey::has_rgb() const {
    std::lock_guard lock(mutex_);
    if (!has_rgb_) has_rgb_ = viewer::chunk_points_have_rgb(*grid_);
    return *has_rgb_;
}

// render's auto intensity range (2nd-98th percentile) over every chunk point.
std::array<float, 2> Survey::intensity_range() const {
    const auto cells = grid_->cells();
    const auto sets = viewer::overview_point_sets(*grid_, cells, {});
    std::vector<render::PointBatch> batches;
    for (const auto& s : sets) batches.push_back(s.batch());
    return render::auto_intensity_range(batches);
}

EncodedPtr Survey::tiles() {
    return cache_.get(fmt::format("{}:tiles", generation_), [this] {
        nlohmann::json names = nlohmann::json::array(), boxes = nlohmann::json::array(),
                       points = nlohmann::json::array();
        for (const auto& t : dataset_.tiles) {
            const auto& b = t.bounds_m;
            names.push_back(file_name(t.tile.path()));
            for (const double v : {b.min_x - grid_->origin_x(), b.min_y - grid_->origin_y(), b.min_z,
                                   b.max_x - grid_->origin_x(), b.max_y - grid_->origin_y(), b.max_z}) {
                boxes.push_back(decimetres(v));
            }
            points.push_back(t.tile.header.point_count);
        }
        return encode(nlohmann::json{{"names", names}, {"boxes_dm", boxes}, {"points", points}}.dump(),
                      dataset_.tiles.size());
    });
}

std::string Survey::cells_body() const {
    std::string out;
    const auto cells = grid_->cells();
    const auto count = static_cast<std::uint32_t>(cells.size());
    out.append(reinterpret_cast<const char*>(&count), 4);
    for (const auto& c : cells) {
        const std::uint32_t n = static_cast<std::uint32_t>(grid_->points_in(c).size());
        out.append(reinterpret_cast<const char*>(&c.ix), 4);
        out.append(reinterpret_cast<const char*>(&c.iy), 4);
        out.append(reinterpret_cast<const char*>(&n), 4);
    }
    return out;
}

// The cache key of a batch of cells with the points each holds now (their counts), so that a
// cell that grows while loading is a new key and a batch encodes exactly the counted points.
std::string Survey::points_key(std::span<const CellKey> cells, std::vector<std::size_t>& counts) const {
    std::string key = fmt::format("{}:p", generation_);
    for (const auto& c : cells) {
        counts.push_back(grid_->points_in(c).size());
        key += fmt::format(":{},{},{}", c.ix, c.iy, counts.back());
    }
    return key;
}

EncodedPtr Survey::cell_points(std::span<const CellKey> cells, std::uint32_t attributes) {
    std::vector<std::size_t> counts;
    const std::string key = points_key(cells, counts) + fmt::format(":a{}", attributes);
    return cache_.get(key, [&] {
        std::string body;
        std::uint64_t n = 0;
        for (std::size_t i = 0; i < cells.size(); ++i) {
            const auto set = viewer::cell_point_set(*grid_, cells[i]);  // origin: the cell's corner at z 0
            const auto points = std::span(set.points).first(std::min(set.points.size(), counts[i]));
            append_block(body, cells[i].ix, cells[i].iy, points, grid_->patch_size(), attributes);
            n += points.size();
        }
        return encode(body, n);
    });
}

void Survey::stop_if_gone(const ClientGone& gone) {
    if (!gone || !gone()) return;
    ++cancelled_;
    throw Error("cancelled: the client has gone");
}

// A decoding slot, waited for while the client is there (a gone client's request leaves the queue).
void Survey::acquire_decode_slot(const ClientGone& gone) {
    using namespace std::chrono_literals;
    stop_if_gone(gone);
    while (!decodes_.try_acquire_for(20ms)) stop_if_gone(gone);
    try {
        stop_if_gone(gone);
    } catch (...) {
        decodes_.release();
        throw;
    }
}

// The heightmaps of `cells`, kHeightmapCellsPerStep at a time while the client is there.
std::vector<viewer::PatchHeightmap> Survey::build_heightmaps(std::span<const CellKey> cells, bool cnn,
                                                             const ClientGone& gone) {
    viewer::HeightmapBuildOptions opt;
    opt.patch.has_rgb = has_rgb();
    opt.footprints = footprints_;
    ThreadPool pool(1);  // on this request's thread: the server's threads are the parallelism
    std::vector<viewer::PatchHeightmap> maps;
    for (std::size_t at = 0; at < cells.size(); at += kHeightmapCellsPerStep) {
        stop_if_gone(gone);
        const auto part = cells.subspan(at, std::min(kHeightmapCellsPerStep, cells.size() - at));
        std::vector<viewer::PatchHeightmap> built;
        if (cnn) {
            std::lock_guard lock(network_mutex_);
            if (!network_) network_ = std::make_unique<nn::HeightmapNetwork>(nn::HeightmapNetwork::load(model_path_));
            built = viewer::build_cnn_heightmaps(*grid_, part, *network_, opt, pool);
        } else {
            built = viewer::build_linear_heightmaps(*grid_, part, opt, pool);
        }
        heightmaps_built_ += built.size();
        std::move(built.begin(), built.end(), std::back_inserter(maps));
    }
    return maps;
}

std::optional<EncodedPtr> Survey::heightmaps(std::span<const CellKey> cells, bool cnn, int step, bool detail,
                                             const ClientGone& gone) {
    if (cnn && model_path_.empty()) throw Error("no heightmap network on this server (serve --model FILE)");
    if (step != 1 && step != 2 && step != 4 && step != 8 && step != 16) throw Error("step must be 1, 2, 4, 8 or 16");
    if (!loader_->finished()) return std::nullopt;
    std::uint64_t version = 0;
    if (detail) {
        std::lock_guard lock(detail_mutex_);
        version = detail_version_;
    }
    std::string key = fmt::format("{}:{}:s{}:d{}", generation_, cnn ? "n" : "h", step, detail ? version + 1 : 0);
    for (const auto& c : cells) key += fmt::format(":{},{}", c.ix, c.iy);
    return cache_.get(key, [&] {
        auto maps = build_heightmaps(cells, cnn, gone);
        if (detail) {
            std::lock_guard lock(detail_mutex_);
            for (auto& h : maps) {
                const auto it = details_.find(h.cell);
                if (it != details_.end()) h = viewer::overlay_detail(h, it->second);
            }
        }
        std::string body;
        for (const auto& h : maps) append_heightmap(body, coarsened(h, step), grid_->origin_x(), grid_->origin_y());
        return encode(body, maps.size());
    });
}

// The tile's points per heightmap texel merged into the survey's detail (while it stays within a
// tenth of the cache's budget: beyond, the heightmaps keep what they learnt so far).
void Survey::learn_detail(const viewer::PointSet& set) {
    auto learnt = viewer::tile_detail(set, *grid_, viewer::HeightmapBuildOptions{}.patch.spec.patch_texels);
    std::lock_guard lock(detail_mutex_);
    for (auto& [cell, d] : learnt) {
        const auto it = details_.find(cell);
        if (it != details_.end()) {
            detail_bytes_ -= it->second.bytes();
            viewer::merge_detail(it->second, d);
            detail_bytes_ += it->second.bytes();
        } else if (detail_bytes_ + d.bytes() <= cache_.budget() / 10) {
            detail_bytes_ += d.bytes();
            details_.emplace(cell, std::move(d));
        }
    }
    ++detail_version_;
}

EncodedPtr Survey::level(std::size_t tile, int level, std::uint32_t attributes, const ClientGone& gone) {
    if (tile >= dataset_.tiles.size()) throw Error("no tile " + std::to_string(tile));
    if (level < 0 || level >= kLevels) throw Error("no level " + std::to_string(level) + " (0-3)");
    const auto key = [&](int l) { return fmt::format("{}:l:{}:{}:a{}", generation_, tile, l, attributes); };
    return cache_.get(key(level), [&] {
        ThreadPool pool(1);  // on this request's thread, as the heightmaps
        acquire_decode_slot(gone);
        struct Release {
            std::counting_semaphore<>& s;
            ~Release() { s.release(); }
        } release{decodes_};
        std::vector<dataset::SkippedChunk> skipped;  // a corrupt chunk costs its points only
        const auto set = viewer::tile_point_set(dataset_.tiles[tile], dataset_.las_stride, pool, {}, &skipped);
        ++tiles_decoded_;
        learn_detail(set);
        auto levels = encode_levels(set, grid_->origin_x(), grid_->origin_y(), attributes);
        EncodedPtr wanted;
        for (int l = 0; l < kLevels; ++l) {  // the tile is decoded once for all its levels
            auto e = encode(levels[l].body, levels[l].points);
            if (l == level) wanted = e;
            else cache_.put(key(l), e);
        }
        return wanted;
    });
}

std::string Survey::stats_json() const {
    return nlohmann::json{{"tiles_decoded", tiles_decoded_.load()}, {"heightmaps_built", heightmaps_built_.load()},
                          {"cancelled", cancelled_.load()}}
        .dump();
}

std::string Survey::auto_camera_json(int width, int height, double fov_deg, std::optional<std::size_t> tile) const {
    if (tile && *tile >= dataset_.tiles.size()) throw Error("no tile " + std::to_string(*tile));
    const auto& b = tile ? dataset_.tiles[*tile].bounds_m : dataset_.bounds_m;
    const auto c = render::Camera::looking_at_bounds(b.min_x, b.min_y, b.min_z, b.max_x, b.max_y, b.max_z, width,
                                                     height, fov_deg);
    const auto& f = dataset_.frame;
    return nlohmann::json{{"x_m", c.x - grid_->origin_x()}, {"y_m", c.y - grid_->origin_y()}, {"z_m", c.z},
                          {"yaw_deg", c.yaw_deg}, {"pitch_deg", c.pitch_deg}, {"fov_deg", c.fov_deg},
                          {"near_m", c.near_m}, {"far_m", c.far_m},
                          {"text", fmt::format("{:.2f},{:.2f},{:.2f},{:g},{:g}", c.x / f.xy_to_metres,
                                               c.y / f.xy_to_metres, c.z / f.z_to_metres, c.yaw_deg, c.pitch_deg)}}
        .dump();
}

}  // namespace lidarscout::serve
