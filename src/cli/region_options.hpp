// What `clip` and `profile` share at the CLI edge (their filter options: cli/filter_options.hpp):
// opening the dataset, the points progress bar, the report of the region read (tiles touched and
// decoded, points, skipped tiles and chunks) for people and --json, and the --force of their LAS/LAZ
// output.
#pragma once

#include <nlohmann/json.hpp>

#include <functional>
#include <string>
#include <vector>

#include "dataset/dataset.hpp"
#include "pipelines/region_points.hpp"

namespace CLI {
class App;
}

namespace lidarscout::cli {

// open_with_progress, skipped files and warnings on stderr, refused without a readable tile; a frame
// in degrees only when `accept_degrees` (dataset::DatasetOptions).
// `base` gives the other options (e.g. sources_found). With `touches` (a region's: x/y bounds in the
// CRS's units), a catalog whose items place every tile opens placed and keeps the tiles it touches alone,
// only their headers read (dataset::keep_tiles_touching).
dataset::Dataset open_region_dataset(const std::vector<std::string>& paths, const std::string& crs,
                                     const std::string& command, bool accept_degrees = false,
                                     dataset::DatasetOptions base = {},
                                     const std::function<bool(const dataset::Bounds&)>& touches = {});

// A "COMMAND: points" progress bar for read_region_points.
class PointsBar {
public:
    explicit PointsBar(const std::string& command);
    ~PointsBar();
    pipelines::PointProgressFn fn();

private:
    struct State;
    std::unique_ptr<State> state_;
};

// tiles_touched, tiles_decoded, points_read, points_kept, points_skipped, skipped: [{file, offset, cause}]
// (chunks and tiles left out while reading, then files the dataset could not open).
nlohmann::json region_stats_json(const pipelines::RegionReadStats& stats, const dataset::Dataset& ds);
// One stderr line per skipped tile or chunk; the exit status (3 when anything was skipped).
int report_skips(const pipelines::RegionReadStats& stats, const dataset::Dataset& ds);

// --force: what a LAS/LAZ output cannot hold (waveform data, a CRS as WKT) dropped with a note instead
// of refused (pipelines::ClipRequest::force).
void add_force_flag(CLI::App& cmd, bool& force);

}  // namespace lidarscout::cli
