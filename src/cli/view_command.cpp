// `lidarscout view [PATH...]`: the interactive viewer (src/viewer/app). Without PATH it opens
// the built-in demo landscape, generated once (synth terrain) into the user's cache folder.
#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <charconv>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <thread>

#include "cli/commands.hpp"
#include "cli/diagnostic_output.hpp"
#include "cli/filter_options.hpp"
#include "cli/json_output.hpp"
#include "cli/number_options.hpp"
#include "cli/io_options.hpp"
#include "cli/network_stats.hpp"
#include "cli/recon_options.hpp"
#include "cli/progress.hpp"
#include "cli/size_options.hpp"
#include "cli/thread_options.hpp"
#include "core/error.hpp"
#include "core/thread_pool.hpp"
#include "io/output_file.hpp"
#include "net/range_cache.hpp"
#include "net/url.hpp"
#include "nn/heightmap_network.hpp"
#include "render/backend.hpp"
#include "synth/terrain_generator.hpp"
#include "viewer/app/viewer_app.hpp"
#include "viewer/overview_cache.hpp"
#include "viewer/profile_tool.hpp"
#include "viewer/session_file.hpp"

namespace lidarscout::cli {
namespace {

struct ViewCliOptions {
    std::vector<std::string> paths;
    FilterTexts filter;  // the points drawn at first
    std::string session, save_session;  // --session FILE, --save-session FILE
    bool area = false;
    std::string clip_out;               // --clip-out FILE.laz (with --area)
    std::string profile, profile_out;   // --profile x0,y0,x1,y1,width, --profile-out FILE
    std::string size = "1280x720";
    std::string memory;
    std::string model;
    std::string crs;
    bool no_cnn = false;
    double demo_km = 2.0;
    double demo_density = 4.0;
    std::string screenshot;
    std::string window_screenshot;
    double quit_after = 0;
    std::vector<std::string> clicks;
    bool measure = false;
    unsigned threads = 0;
    std::string backend = "cpu";
    std::string stats_json;
    bool no_cache = false;    // --no-cache (not --cache): no overview sidecar of a remote dataset kept or used
    bool no_overview = false; // --no-overview given (no sidecar used, none kept)
};

// "X,Y" window pixels of a scripted click.
std::pair<double, double> parse_click(const std::string& text) {
    const auto xy = parse_number_list(text, "--click");
    if (xy.size() != 2) throw Error::in_stage("view", "--click wants X,Y in window pixels, not '" + text + "'");
    return {xy[0], xy[1]};
}

// $XDG_CACHE_HOME/lidarscout or ~/.cache/lidarscout.
std::filesystem::path cache_folder() {
    if (const char* xdg = std::getenv("XDG_CACHE_HOME"); xdg && *xdg) return std::filesystem::path(xdg) / "lidarscout";
    if (const char* home = std::getenv("HOME"); home && *home) {
        return std::filesystem::path(home) / ".cache" / "lidarscout";
    }
    throw Error::in_stage("view", "no cache folder for the demo (neither XDG_CACHE_HOME nor HOME is set); give a PATH");
}

// Where a remote dataset's overview sidecar is kept (viewer/overview_cache.hpp): unset for local paths,
// --no-cache, --no-overview, --cache-size 0 or no cache folder.
std::optional<viewer::OverviewCacheSettings> overview_cache(const ViewCliOptions& o,
                                                            const std::vector<std::string>& paths) {
    const std::uint64_t bound = net::RangeCache::shared().max_bytes();
    const auto url = [](const std::string& p) { return net::is_url(p); };
    const bool remote = !paths.empty() && std::all_of(paths.begin(), paths.end(), url);
    if (o.no_cache || o.no_overview || bound == 0 || !remote) return std::nullopt;
    try {
        return viewer::OverviewCacheSettings{cache_folder() / "overviews", bound};
    } catch (const Error&) {
        return std::nullopt;  // (neither XDG_CACHE_HOME nor HOME: nothing kept)
    }
}

// The demo's folder, generated on first use (the manifest is written last: its presence says done).
std::string demo_folder(const ViewCliOptions& o) {
    synth::TerrainOptions t;
    t.km = o.demo_km, t.density = o.demo_density;
    const synth::Area area = synth::terrain_area(t);  // validates
    const bool standard = o.demo_km == 2.0 && o.demo_density == 4.0;
    const auto dir = cache_folder() / (standard ? std::string("demo")
                                                : "demo-" + std::to_string(t.km).substr(0, 4) + "km-" +
                                                      std::to_string(t.density).substr(0, 4));
    if (std::filesystem::exists(dir / synth::kTerrainManifest)) return dir.string();
    std::fprintf(stderr, "lidarscout: generating the demo landscape (%.1f km, %.0f points/m2) into %s\n", t.km,
                 t.density, dir.c_str());
    ThreadPool pool(o.threads ? o.threads : std::max(1u, std::thread::hardware_concurrency()));
    Progress progress("demo tiles", std::uint64_t{area.tiles} * area.tiles);
    synth::generate_terrain(t, dir.string(), pool, [&](const synth::TerrainTile&) { progress.add(1); });
    progress.finish();
    return dir.string();
}

// The --backend option resolved: an error for an unavailable `cuda`, a note when `auto` falls back.
render::Backend resolve_backend(const std::string& text) {
    const render::BackendChoice choice = render::choose_backend(render::parse_backend(text));
    if (!choice.note.empty()) std::fprintf(stderr, "lidarscout: %s; drawing on the CPU\n", choice.note.c_str());
    return choice.backend;
}

nlohmann::json seconds(const std::optional<double>& s) { return s ? nlohmann::json(*s) : nlohmann::json(nullptr); }

// --stats-json: when the window showed what (viewer_app.hpp's ViewerTimings), null for never; the
// memory figures (bytes); and what its remote reads cost (requests, bytes, per tile: cli/network_stats.hpp).
void write_stats_json(const std::string& path, const viewer::app::ViewerTimings& t, const net::HttpStats& network) {
    nlohmann::json j = {{"first_frame_s", seconds(t.first_frame_s)},
                        {"footprints_s", seconds(t.footprints_s)},
                        {"dataset_open_s", seconds(t.dataset_open_s)},
                        {"first_overview_s", seconds(t.first_overview_s)},
                        {"chunk_points_s", seconds(t.chunk_points_s)},
                        {"nearest_full_s", seconds(t.nearest_full_s)},
                        {"frames_while_opening", t.frames_while_opening},
                        {"tiles", t.tiles},
                        {"skipped", t.skipped},
                        {"peak_resident_bytes", t.peak_resident_bytes},
                        {"memory_budget_bytes", t.budget_bytes},
                        {"data_budget_bytes", t.data_budget_bytes},
                        {"ledger_peak_bytes", t.ledger_peak_bytes},
                        {"outside_data_bytes", t.outside_bytes},
                        {"memory_note", t.budget_note},
                        {"overview_note", t.overview_note}};
    j.update(network_json(network, t.tiles));
    const std::string text = json_text(j) + "\n";
    io::AtomicOutputFile out(path);
    out.write({reinterpret_cast<const std::uint8_t*>(text.data()), text.size()});
    out.commit();
}

int run_view(const ViewCliOptions& o) {
    viewer::app::ViewerOptions v;
    v.backend = resolve_backend(o.backend);
    std::tie(v.width, v.height) = parse_pixels(o.size, 64);
    v.memory_budget = o.memory.empty() ? 0 : parse_bytes(o.memory);
    v.cnn = !o.no_cnn;
    if (!o.model.empty() && !o.no_cnn) nn::check_model_file(o.model);  // named here, not only in the window
    v.model = o.model;
    v.crs = o.crs;
    v.screenshot = o.screenshot;
    v.window_screenshot = o.window_screenshot;
    v.quit_after = o.quit_after;
    for (const auto& c : o.clicks) v.clicks.push_back(parse_click(c));
    v.measure = o.measure;
    v.area = o.area;
    if (!o.clip_out.empty() && (!o.area || o.clicks.size() < 3 || o.quit_after <= 0)) {
        throw Error::in_stage("view", "--clip-out wants --area, at least three --click vertices and --quit-after");
    }
    v.clip_out = o.clip_out;
    if (!o.profile.empty()) v.profile = viewer::parse_corridor(o.profile);
    if (!o.profile_out.empty() && (!v.profile || o.quit_after <= 0)) {
        throw Error::in_stage("view", "--profile-out wants --profile and --quit-after");
    }
    v.profile_out = o.profile_out;
    v.filter = o.filter.filter();
    if (!o.session.empty()) {
        v.session = viewer::read_session(o.session);
        print_diagnostics(v.session->notes);  // a yaw wrapped, a pitch clamped
        v.session_path = o.session;
        if (v.crs.empty()) v.crs = v.session->crs;
        const bool filtered = !o.filter.classes.empty() || !o.filter.returns.empty() || !o.filter.intensity.empty();
        if (filtered) v.session->filter = v.filter;  // the command line's filter wins over the saved one
    }
    v.save_session = o.save_session;
    v.threads = o.threads;
    v.paths = o.paths;
    if (v.paths.empty() && v.session) v.paths = v.session->paths;  // the session's dataset
    if (v.paths.empty()) v.paths = {demo_folder(o)};
    v.overview_cache = overview_cache(o, v.paths);
    viewer::app::ViewerTimings timings;
    const net::HttpStats network_before = net::HttpClient::shared().stats();
    const int status = viewer::app::run_viewer(v, &timings);
    if (!o.stats_json.empty()) write_stats_json(o.stats_json, timings, network_since(network_before));
    return status;
}

}  // namespace

void register_view_command(CLI::App& app, std::function<int()>& run) {
    auto o = std::make_shared<ViewCliOptions>();
    auto* cmd = app.add_subcommand("view", "Open a window on LAS/LAZ tiles (or the built-in demo) and explore them: "
                                           "chunk points at once, heightmaps, full resolution near the camera");
    add_inputs(*cmd, "paths", o->paths,
               "LAS/LAZ files, folders, tile lists, EPT datasets or http(s) or s3:// URLs (none: the demo landscape)");
    cmd->add_option("--size", o->size, "Window size WIDTHxHEIGHT (default 1280x720)");
    const std::string overviews = (net::default_cache_folder().parent_path() / "overviews").string();
    const std::string keep_help =
        "Remote datasets (URLs): keep an overview sidecar of what was opened (every tile's metadata and chunk "
        "points) in " + overviews + " once they are in, so that the next view of the same URLs opens from it, asking "
        "the tiles for nothing but full resolution (a tile changed since is named and read itself); bounded by "
        "--cache-size, the least recently used dropped (the default)";
    auto* keep = cmd->add_flag("--cache", keep_help);
    cmd->add_flag("--no-cache", o->no_cache, "Neither keep nor use an overview sidecar of a remote dataset in " +
                  overviews + " (--cache)")->excludes(keep);
    cmd->add_option("--memory", o->memory, "Memory budget, e.g. 4G (default: a quarter of the RAM)");
    cmd->add_option("--model", o->model, "Heightmap network (default: models/heightmap_cnn.pt; none: linear only)");
    cmd->add_option("--crs", o->crs,
                    "Reproject every tile to this CRS, e.g. EPSG:32632 (default: the CRS most tiles use)");
    cmd->add_flag("--no-cnn", o->no_cnn, "Linear heightmaps only, no network");
    cmd->add_option("--demo-km", o->demo_km, "Side of the demo landscape in km (default 2)")
        ->check(CLI::Range(0.5, 20.0));
    cmd->add_option("--demo-density", o->demo_density, "Points per m2 of the demo (default 4)")
        ->check(CLI::Range(0.5, 50.0));
    add_output(*cmd, "--screenshot", o->screenshot, "Write the last frame to this PNG on exit (scripted use)",
               io::OutputKind::Png);
    add_output(*cmd, "--window-screenshot", o->window_screenshot,
               "Write the whole window, panels included, to this PNG on exit (scripted use)", io::OutputKind::Png);
    cmd->add_option("--click", o->clicks, "Click at window pixel X,Y just before quitting (scripted use; repeatable)");
    add_filter_options(*cmd, o->filter, "points drawn at first (the Filters section changes them)");
    // A document the user edits, not data: the panel's "save session" saves back to it when asked.
    cmd->add_option("--session", o->session,
                    "Open a saved session (.lidarscout.json: its paths unless PATH is given, CRS, camera, filter, "
                    "colour, measurements, labels); the panel's \"save session\" saves back to it");
    add_output(*cmd, "--save-session", o->save_session, "Write the session to this .json when the viewer ends "
               "(scripted use)", io::OutputKind::Json);
    cmd->add_flag("--area", o->area,
                  "Scripted clicks are a polygon's vertices: prints its area, surface, and the volume above (cut) "
                  "and below (fill) the plane through them, from the points held and drawn");
    add_output(*cmd, "--clip-out", o->clip_out,
               "With --area: write the points inside the clicked polygon (every point of the tiles under it that "
               "the filter keeps, as `clip` writes them) to this .laz/.las (scripted use)",
               io::OutputKind::PointCloud);
    cmd->add_option("--profile", o->profile,
                    "Open the profile of the corridor x0,y0,x1,y1,width (the dataset CRS's units, as `profile "
                    "--line` and `--width`) at start");
    add_output(*cmd, "--profile-out", o->profile_out,
               "With --profile: write it, once read, to this .csv, .laz/.las or .png, as `profile -o` does, and "
               "print its points count (scripted use)",
               io::OutputKind::Profile);
    cmd->add_flag("--measure", o->measure, "Scripted clicks measure between points instead of inspecting one");
    cmd->add_option("--quit-after", o->quit_after, "Quit this many seconds after the dataset is open (scripted use)")
        ->check(non_negative_number());
    add_thread_option(*cmd, "--threads", o->threads, "Rendering threads (default: all cores)");
    cmd->add_option("--backend", o->backend,
                    "Rasterizer: cpu (default), cuda (the GPU plugin; an error when unavailable) or auto (cuda when "
                    "available, else cpu)");
    add_output(*cmd, "--stats-json", o->stats_json,
               "Write to this JSON file on exit the seconds from the start to the first frame, to the first with "
               "every tile's footprint, to the dataset open, to the first frame with heightmaps, to all chunk "
               "points in and to the tile nearest the camera at full resolution, and the HTTP requests and bytes "
               "of a remote dataset, also per tile (scripted use)",
               io::OutputKind::Json);
    cmd->callback([o, cmd, &run] {
        o->no_overview = cmd->count("--no-overview") > 0;
        run = [o] { return run_view(*o); };
    });
}

}  // namespace lidarscout::cli
