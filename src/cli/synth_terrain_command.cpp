// `lidarscout synth terrain -o DIR [--km 4] [--density 8] [--seed N] [--threads N] [--json]`:
// writes the built-in demo landscape as 500 m LAZ tiles (see synth/terrain_generator.hpp).
#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <thread>

#include "cli/commands.hpp"
#include "cli/json_output.hpp"
#include "cli/io_options.hpp"
#include "cli/progress.hpp"
#include "cli/thread_options.hpp"
#include "core/thread_pool.hpp"
#include "synth/terrain_generator.hpp"

namespace lidarscout::cli {
namespace {

struct TerrainCliOptions {
    std::string out;
    synth::TerrainOptions terrain;
    unsigned threads = 0;
    bool json = false;
};

nlohmann::json to_json(const synth::TerrainResult& r, const TerrainCliOptions& o, double secs) {
    nlohmann::json files = nlohmann::json::array();
    for (const auto& t : r.tiles) {
        files.push_back({{"path", t.path}, {"ix", t.ix}, {"iy", t.iy}, {"points", t.points}, {"chunks", t.chunks},
                         {"bytes", t.bytes}});
    }
    return {{"output", o.out},
            {"seed", o.terrain.seed},
            {"km", r.area.size() / 1000.0},
            {"density", o.terrain.density},
            {"origin", {r.area.x0, r.area.y0}},
            {"tiles", r.tiles.size()},
            {"points", r.points},
            {"bytes", r.bytes},
            {"points_per_m2", r.points / (r.area.size() * r.area.size())},
            {"seconds", secs},
            {"files", files}};
}

int run_terrain(const TerrainCliOptions& o) {
    const synth::Area area = synth::terrain_area(o.terrain);  // validates before anything is written
    ThreadPool pool(o.threads ? o.threads : std::max(1u, std::thread::hardware_concurrency()));
    const auto t0 = std::chrono::steady_clock::now();
    Progress progress("synth terrain (tiles)", std::uint64_t{area.tiles} * area.tiles);
    const auto result =
        synth::generate_terrain(o.terrain, o.out, pool, [&](const synth::TerrainTile&) { progress.add(1); });
    progress.finish();
    const double secs = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    if (o.json) {
        print_json_answer(to_json(result, o, secs));
    } else {
        std::printf(
            "%s: %zu tiles of 500 m (%.1f x %.1f km), %llu points (%.2f per m2), %llu bytes in %.2f s (%.2f M "
            "points/s)\n",
            o.out.c_str(), result.tiles.size(), area.size() / 1000.0, area.size() / 1000.0,
            static_cast<unsigned long long>(result.points), result.points / (area.size() * area.size()),
            static_cast<unsigned long long>(result.bytes), secs, secs > 0 ? result.points / secs / 1e6 : 0.0);
    }
    return 0;
}

}  // namespace

void register_synth_terrain(CLI::App& synth, std::function<int()>& run) {
    auto o = std::make_shared<TerrainCliOptions>();
    auto* cmd = synth.add_subcommand("terrain",
                                     "Write the demo landscape (relief, river, roads, buildings, trees) as 500 m LAZ "
                                     "tiles, deterministic for a seed");
    add_output(*cmd, "-o,--output", o->out, "Output folder (created if needed; earlier demo tiles in it are replaced)",
               io::OutputKind::Folder)
        ->required();
    cmd->add_option("--km", o->terrain.km, "Side of the square area in km, rounded up to 500 m tiles (default 4)");
    cmd->add_option("--density", o->terrain.density, "Points per square metre (default 8)");
    cmd->add_option("--seed", o->terrain.seed, "Seed of the landscape (default 1)");
    add_thread_option(*cmd, "--threads", o->threads, "Threads (default: all cores); the output does not depend on it");
    cmd->add_flag("--json", o->json, "Print the result as JSON");
    cmd->callback([o, &run] { run = [o] { return run_terrain(*o); }; });
}

}  // namespace lidarscout::cli
