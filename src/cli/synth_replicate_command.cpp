// `lidarscout synth replicate SRC... -o DIR --grid NXxNY [--virtual] [--threads N] [--json]`: a
// large dataset for benchmarks, made by copying real tiles onto a grid (see synth/replicate.hpp),
// or with --virtual only its manifest, opened as the tiles without copying
// (dataset/virtual_replica.hpp).
// A benchmark tool, not a data product.
#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <thread>

#include "cli/commands.hpp"
#include "cli/json_output.hpp"
#include "cli/io_options.hpp"
#include "cli/diagnostic_output.hpp"
#include "cli/progress.hpp"
#include "cli/thread_options.hpp"
#include "core/error.hpp"
#include "core/thread_pool.hpp"
#include "synth/replicate.hpp"

namespace lidarscout::cli {
namespace {

struct ReplicateCliOptions {
    std::vector<std::string> sources;
    std::string out_dir;
    std::string grid;
    unsigned threads = 0;
    bool json = false;
    bool virtual_tiles = false;
};

constexpr const char* kPurpose =
    "A benchmark tool, not a data product: copies real tiles onto an NXxNY grid, moving only the "
    "header's x/y offsets and bounds (and a COPC centre). Points repeat from tile to tile and "
    "neighbouring tiles do not join.\n";

void print_summary(const synth::ReplicatePlan& plan, double secs, bool json, bool virtual_tiles) {
    const double gb = plan.total_bytes / 1e9;
    const double rate = secs > 0 ? gb / secs : 0.0;
    const auto manifest = (std::filesystem::path(plan.out_dir) / synth::kManifestName).string();
    if (json) {
        nlohmann::json j = {{"output", plan.out_dir}, {"manifest", manifest}, {"grid", {plan.grid.nx, plan.grid.ny}},
                            {"cell_metres", plan.cell_metres}, {"sources", plan.sources.size()},
                            {"virtual", virtual_tiles}, {"tiles", plan.tiles.size()}, {"bytes", plan.total_bytes},
                            {"points", plan.total_points}, {"seconds", secs}, {"gb_per_s", rate},
                            {"warnings", plan.warnings.messages()},
                            {"diagnostics", diagnostics_json(plan.warnings)}};
        print_json_answer(j);
        return;
    }
    if (virtual_tiles) {
        std::printf("%s: a virtual replica of %zu tiles (%ux%u grid of %.0f m cells from %zu sources), %llu points, "
                    "%.2f GB as if copied, nothing copied; benchmark data, not a data product. Open it with: "
                    "lidarscout view %s\n",
                    plan.out_dir.c_str(), plan.tiles.size(), plan.grid.nx, plan.grid.ny, plan.cell_metres,
                    plan.sources.size(), (unsigned long long)plan.total_points, gb, manifest.c_str());
        return;
    }
    std::printf("%s: %zu tiles (%ux%u grid of %.0f m cells from %zu sources), %llu points, %.2f GB in %.2f s "
                "(%.2f GB/s); benchmark data, not a data product (manifest: %s)\n",
                plan.out_dir.c_str(), plan.tiles.size(), plan.grid.nx, plan.grid.ny, plan.cell_metres,
                plan.sources.size(), (unsigned long long)plan.total_points, gb, secs, rate, manifest.c_str());
}

int run_replicate(const ReplicateCliOptions& o) {
    const auto grid = synth::parse_grid(o.grid);
    const auto t0 = std::chrono::steady_clock::now();
    const auto plan = synth::plan_replicas(o.sources, o.out_dir, grid);
    print_diagnostics(plan.warnings);
    if (o.virtual_tiles) {
        synth::write_virtual_replica(plan);
        print_summary(plan, 0, o.json, true);
        return 0;
    }
    ThreadPool pool(o.threads ? o.threads : std::max(1u, std::thread::hardware_concurrency()));
    {
        Progress progress("replicate", plan.total_bytes);
        synth::write_replicas(plan, pool, [&](std::uint64_t bytes) { progress.add(bytes); });
        progress.finish();
    }
    const double secs = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    print_summary(plan, secs, o.json, false);
    return 0;
}

}  // namespace

void register_synth_replicate(CLI::App& synth, std::function<int()>& run) {
    auto o = std::make_shared<ReplicateCliOptions>();
    auto* cmd = synth.add_subcommand(
        "replicate", "Benchmark tool, not a data product: write a large dataset by copying real tiles onto a grid");
    cmd->footer(kPurpose);
    add_inputs(*cmd, "sources", o->sources, "Source LAS/LAZ files or folders (searched recursively)")->required();
    add_output(*cmd, "-o,--output", o->out_dir,
               "Output folder (created if missing; must not hold a source). Tiles are named "
               "STEM_xGX_yGY.laz, with a replicate.json manifest",
               io::OutputKind::Folder)
        ->required();
    cmd->add_option("--grid", o->grid, "Grid size NXxNY, e.g. 45x45 (tile GX,GY copies source (GX + GY*NX) mod N)")
        ->required();
    add_thread_option(*cmd, "--threads", o->threads, "Files copied in parallel (default: all cores)");
    cmd->add_flag("--json", o->json, "Print the summary as JSON");
    cmd->add_flag("--virtual", o->virtual_tiles,
                  "Copy nothing: write only the manifest DIR/replicate.json, which every command opens as the "
                  "tiles (each a source tile with a shift); for benchmarks at any scale without the disk");
    cmd->callback([o, &run] { run = [o] { return run_replicate(*o); }; });
}

}  // namespace lidarscout::cli
