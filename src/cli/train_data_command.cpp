// `lidarscout train-data PATH... -o FILE [--texel 1,2.5,5,10] [--patches N] [--stride auto]
// [--seed S] [--split-block M] [--val-fraction F] [--split-seed S] [--offsets N] [--json]`: exports training samples
// for the heightmap network (layout in src/pipelines/training_data.hpp; python/ reads it with numpy).
#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include <chrono>
#include <cstdio>
#include <thread>

#include "cli/commands.hpp"
#include "cli/json_output.hpp"
#include "cli/number_options.hpp"
#include "cli/io_options.hpp"
#include "cli/progress.hpp"
#include "cli/recon_options.hpp"
#include "cli/thread_options.hpp"
#include "core/error.hpp"
#include "core/thread_pool.hpp"
#include "dataset/dataset.hpp"
#include "pipelines/training_data.hpp"

namespace lidarscout::cli {
namespace {

struct TrainDataCliOptions {
    std::vector<std::string> paths;
    std::string out;
    std::string texels = "10";
    std::size_t patches = 100;
    std::uint64_t seed = 1;
    std::string stride = "auto";
    pipelines::RegionSplitOptions split;
    int offsets = 1;
    unsigned threads = 0;
    bool json = false;
};

int run_train_data(const TrainDataCliOptions& o) {
    pipelines::TrainingDataOptions opt;
    opt.texels_m = parse_number_list(o.texels, "--texel");
    opt.patches = o.patches;
    opt.seed = o.seed;
    opt.stride = parse_stride(o.stride);
    opt.split = o.split;
    opt.offsets = o.offsets;
    ThreadPool pool(o.threads ? o.threads : std::max(1u, std::thread::hardware_concurrency()));

    std::vector<dataset::Dataset> datasets;
    datasets.reserve(o.paths.size());
    std::vector<pipelines::NamedDataset> named;
    std::uint64_t total = 0;
    for (const auto& path : o.paths) {
        datasets.push_back(open_reported_dataset(path));
        total += datasets.back().point_count;
    }
    for (std::size_t i = 0; i < o.paths.size(); ++i) named.push_back({dataset_name(o.paths[i]), &datasets[i]});

    const auto t0 = std::chrono::steady_clock::now();
    Progress progress("train-data", total);
    std::uint64_t before = 0, shown = 0;  // points of the finished datasets, points drawn
    std::size_t current = 0;
    const auto s =
        pipelines::write_training_data(named, opt, o.out, pool, [&](std::size_t d, std::uint64_t done, std::uint64_t) {
            for (; current < d; ++current) before += datasets[current].point_count;
            progress.add(before + done - shown);
            shown = before + done;
        });
    progress.finish();
    const double secs = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    if (o.json) {
        const nlohmann::json j = {{"output", o.out}, {"samples", s.samples}, {"train", s.train},
                                  {"validation", s.validation}, {"dropped_at_split_border", s.dropped_at_split_border},
                                  {"bytes", s.bytes}, {"seconds", secs}};
        print_json_answer(j);
    } else {
        std::printf("%s: %zu samples (%zu train, %zu validation, %zu dropped at split borders), %.1f MB in %.1f s\n",
                    o.out.c_str(), s.samples, s.train, s.validation, s.dropped_at_split_border, s.bytes / 1e6, secs);
    }
    return 0;
}

}  // namespace

void register_train_data_command(CLI::App& app, std::function<int()>& run) {
    auto o = std::make_shared<TrainDataCliOptions>();
    auto* cmd =
        app.add_subcommand("train-data", "Export training samples (inputs and ground truth) for the heightmap network");
    add_inputs(*cmd, "paths", o->paths, "Datasets: each a folder, tile list or file")->required();
    add_output(*cmd, "-o,--output", o->out, "Output file (layout: src/pipelines/training_data.hpp)",
               io::OutputKind::TrainingData)->required();
    cmd->add_option("--texel", o->texels, "Texel sizes in metres, comma-separated (default 10)");
    cmd->add_option("--patches", o->patches, "Patches per dataset and texel size (default 100)")
        ->check(positive_number());
    cmd->add_option("--seed", o->seed, "Seed of the patch choice (default 1)");
    cmd->add_option("--stride", o->stride, "Chunk-point stride K or 'auto' (default; see README)");
    add_split_options(*cmd, o->split);
    add_offsets_option(*cmd, o->offsets);
    add_thread_option(*cmd, "--threads", o->threads, "Decoding threads (default: all cores)");
    cmd->add_flag("--json", o->json, "Print the summary as JSON");
    cmd->callback([o, &run] { run = [o] { return run_train_data(*o); }; });
}

}  // namespace lidarscout::cli
