// The options and report shared by `clip` and `profile`.
#include "cli/region_options.hpp"

#include <CLI/CLI.hpp>

#include <cstdio>
#include <memory>

#include "cli/diagnostic_output.hpp"
#include "cli/progress.hpp"
#include "cli/stage_progress.hpp"

namespace lidarscout::cli {

dataset::Dataset open_region_dataset(const std::vector<std::string>& paths, const std::string& crs,
                                     const std::string& command, bool accept_degrees,
                                     dataset::DatasetOptions base,
                                     const std::function<bool(const dataset::Bounds&)>& touches) {
    dataset::DatasetOptions options = std::move(base);
    options.crs = crs;
    options.accept_degrees = accept_degrees;
    options.placed = static_cast<bool>(touches);
    dataset::Dataset ds = open_with_progress(paths, options);
    if (touches) dataset::keep_tiles_touching(ds, touches, options.io_threads);
    for (const auto& s : ds.skipped) std::fprintf(stderr, "lidarscout: skipped %s\n", s.error.c_str());
    print_diagnostics(ds.warnings);
    dataset::require_tiles(ds, command);
    return ds;
}

struct PointsBar::State {
    std::unique_ptr<Progress> bar;
    std::uint64_t shown = 0;
    std::string label;
};

PointsBar::PointsBar(const std::string& command) : state_(std::make_unique<State>()) {
    state_->label = command + ": points";
}
PointsBar::~PointsBar() = default;

pipelines::PointProgressFn PointsBar::fn() {
    return [s = state_.get()](std::uint64_t done, std::uint64_t total) {
        if (!s->bar) s->bar = std::make_unique<Progress>(s->label, total);
        s->bar->add(done - s->shown);
        s->shown = done;
    };
}

namespace {

// The chunks and tiles left out while reading, then the files the dataset could not open.
nlohmann::json skipped_with_files(const pipelines::RegionReadStats& stats, const dataset::Dataset& ds) {
    nlohmann::json list = skipped_json(stats.skipped);
    for (const auto& f : ds.skipped) list.push_back({{"file", f.path}, {"offset", nullptr}, {"cause", f.error}});
    return list;
}

}  // namespace

nlohmann::json region_stats_json(const pipelines::RegionReadStats& stats, const dataset::Dataset& ds) {
    return {{"tiles_touched", stats.tiles_touched.size()},
            {"tiles_decoded", stats.tiles_decoded},
            {"points_read", stats.points_read},
            {"points_kept", stats.points_kept},
            {"points_skipped", stats.points_skipped},
            {"skipped", skipped_with_files(stats, ds)}};
}

int report_skips(const pipelines::RegionReadStats& stats, const dataset::Dataset& ds) {
    print_skipped(stats.skipped);
    return written_exit_status(!stats.skipped.empty() || !ds.skipped.empty());
}

void add_force_flag(CLI::App& cmd, bool& force) {
    cmd.add_flag("--force", force,
                 "Write what the LAS/LAZ output cannot hold dropped, with a note, instead of refusing: waveform data "
                 "(the wave packets then point at none), a CRS that formats 6-10 need as WKT (its GeoTIFF keys kept)");
}

}  // namespace lidarscout::cli
