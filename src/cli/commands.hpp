// The subcommands of the `lidarscout` program; each registers itself on the CLI11 app and
// runs from the callback. They return the process exit status.
#pragma once

#include <functional>

namespace CLI {
class App;
}

namespace lidarscout::cli {

// Registers `info`; sets `run` to the function that executes it once parsed.
void register_info_command(CLI::App& app, std::function<int()>& run);
// Registers `convert`.
void register_convert_command(CLI::App& app, std::function<int()>& run);
// Registers `scan`.
void register_scan_command(CLI::App& app, std::function<int()>& run);
// Registers `eval`.
void register_eval_command(CLI::App& app, std::function<int()>& run);
// Registers `train-data`.
void register_train_data_command(CLI::App& app, std::function<int()>& run);
// Registers `dem` (DEM and orthophoto as Cloud-Optimized GeoTIFF).
void register_dem_command(CLI::App& app, std::function<int()>& run);
// Registers `catalog` (a dataset as a QGIS virtual point cloud, .vpc).
void register_catalog_command(CLI::App& app, std::function<int()>& run);
// Registers `clip` (the points inside a box or polygon as one LAS/LAZ file).
void register_clip_command(CLI::App& app, std::function<int()>& run);
// Registers `profile` (the points of a corridor along a line: CSV, LAS/LAZ or PNG).
void register_profile_command(CLI::App& app, std::function<int()>& run);
// Registers `render` (headless rendering of a dataset to a PNG).
void register_render_command(CLI::App& app, std::function<int()>& run);
// Registers `view` (the interactive viewer).
void register_view_command(CLI::App& app, std::function<int()>& run);
// Registers `serve` (the datasets as a web page and a binary API).
void register_serve_command(CLI::App& app, std::function<int()>& run);
// Registers `synth` with its subcommands (below), each in its own file.
void register_synth_command(CLI::App& app, std::function<int()>& run);
void register_synth_replicate(CLI::App& synth, std::function<int()>& run);
void register_synth_terrain(CLI::App& synth, std::function<int()>& run);

}  // namespace lidarscout::cli
