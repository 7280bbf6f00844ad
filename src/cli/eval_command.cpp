// `lidarscout eval PATH... --methods nearest,linear,cubic,splat,cnn,released [--model FILE]
// [--released-model FILE] [--texel 10]
// [--patches N] [--seed S] [--stride K|auto] [--split validation] [--offsets N] [--json]`:
// scores heightmap reconstruction methods against ground truth from the full-resolution
// points, per dataset (each PATH) and overall.
#include <CLI/CLI.hpp>
#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
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
#include "nn/heightmap_network.hpp"
#include "nn/released_model.hpp"
#include "pipelines/evaluation.hpp"

namespace lidarscout::cli {
namespace {

struct EvalCliOptions {
    std::vector<std::string> paths;
    std::string methods = "nearest,linear,cubic,splat";
    double texel = 10.0;
    std::size_t patches = 100;
    std::uint64_t seed = 1;
    std::string stride = "auto";
    unsigned threads = 0;
    bool json = false;
    std::string model;  // empty: the default model (only loaded for cnn)
    std::string released_model;  // the paper's released ipes_cnn.pt (required for released)
    std::string split = "all";
    pipelines::RegionSplitOptions split_options;
    int offsets = 1;
    std::size_t batch = 16;
};

std::optional<pipelines::Split> parse_split(const std::string& text) {
    if (text == "all") return std::nullopt;
    if (text == "train") return pipelines::Split::Train;
    if (text == "validation") return pipelines::Split::Validation;
    throw Error("--split must be all, train or validation (not '" + text + "')");
}

bool has_method(const std::vector<recon::Method>& methods, recon::Method m) {
    return std::find(methods.begin(), methods.end(), m) != methods.end();
}

std::vector<recon::Method> parse_methods(const std::string& list) {
    std::vector<recon::Method> out;
    std::size_t start = 0;
    while (start <= list.size()) {
        const auto end = std::min(list.find(',', start), list.size());
        if (end > start) out.push_back(recon::method_from_name(list.substr(start, end - start)));
        start = end + 1;
    }
    if (out.empty()) throw Error("--methods names no method");
    return out;
}

// JSON numbers must be finite: NaN (nothing to average) becomes null.
nlohmann::json number(double v) { return std::isfinite(v) ? nlohmann::json(v) : nlohmann::json(nullptr); }

nlohmann::json methods_json(const std::map<recon::Method, pipelines::MethodScores>& methods) {
    nlohmann::json j = nlohmann::json::object();
    for (const auto& [m, s] : methods) {
        const auto rmse = pipelines::summarise(s.rmse_m), psnr = pipelines::summarise(s.psnr_db),
                   ms = pipelines::summarise(s.ms);
        j[std::string(recon::method_name(m))] = {
            {"rmse_m_mean", number(rmse.mean)},         {"rmse_m_std", number(rmse.std)},
            {"psnr_db_mean", number(psnr.mean)},        {"psnr_db_std", number(psnr.std)},
            {"ms_per_patch_median", number(ms.median)}, {"patches", rmse.count}};
    }
    return j;
}

void merge_into(std::map<recon::Method, pipelines::MethodScores>& all, const pipelines::DatasetEvaluation& e) {
    for (const auto& [m, s] : e.methods) {
        auto& a = all[m];
        a.rmse_m.insert(a.rmse_m.end(), s.rmse_m.begin(), s.rmse_m.end());
        a.psnr_db.insert(a.psnr_db.end(), s.psnr_db.begin(), s.psnr_db.end());
        a.ms.insert(a.ms.end(), s.ms.begin(), s.ms.end());
    }
}

void print_table(const std::string& title, const std::map<recon::Method, pipelines::MethodScores>& methods) {
    std::printf("%s\n  %-8s %18s %18s %10s %8s\n", title.c_str(), "method", "height RMSE (m)", "RGB PSNR (dB)",
                "ms/patch", "patches");
    for (const auto& [m, s] : methods) {
        const auto rmse = pipelines::summarise(s.rmse_m), psnr = pipelines::summarise(s.psnr_db),
                   ms = pipelines::summarise(s.ms);
        const std::string psnr_text = psnr.count ? fmt::format("{:.2f} ± {:.2f}", psnr.mean, psnr.std) : "no colour";
        std::printf("  %-8s %18s %18s %10.3f %8zu\n", std::string(recon::method_name(m)).c_str(),
                    fmt::format("{:.3f} ± {:.3f}", rmse.mean, rmse.std).c_str(), psnr_text.c_str(), ms.median,
                    rmse.count);
    }
}

// An evaluation that scored no patch is an error with the reasons (each dataset's counts).
void check_something_scored(const std::map<recon::Method, pipelines::MethodScores>& all,
                            const nlohmann::json& datasets, const EvalCliOptions& o) {
    for (const auto& [method, scores] : all) {
        if (!scores.rmse_m.empty()) return;
    }
    std::string why;
    for (const auto& [name, d] : datasets.items()) {
        why += fmt::format("{}{}: {} candidate patches, {} with too few chunk points, {} with little ground truth, {} "
                           "outside the split", why.empty() ? "" : "; ", name, d.at("candidates").get<std::size_t>(),
                           d.at("too_few_points").get<std::size_t>(), d.at("low_coverage").get<std::size_t>(),
                           d.at("other_split").get<std::size_t>());
    }
    throw Error::in_stage("eval", fmt::format("no patch could be scored at --texel {:g} (patches are 64 texels): {}",
                                              o.texel, why));
}

int run_eval(const EvalCliOptions& o) {
    pipelines::EvalOptions opt;
    opt.methods = parse_methods(o.methods);
    opt.spec.texel_m = o.texel;
    opt.spec.validate();
    opt.patches = o.patches;
    opt.seed = o.seed;
    opt.stride = parse_stride(o.stride);
    opt.split = parse_split(o.split);
    opt.split_options = o.split_options;
    opt.offsets = o.offsets;
    opt.batch = o.batch;
    const unsigned threads = o.threads ? o.threads : std::max(1u, std::thread::hardware_concurrency());
    std::string model_path;
    if (has_method(opt.methods, recon::Method::Released)) {
        if (o.released_model.empty()) throw Error::in_stage("eval", "the released method needs --released-model FILE");
        auto released = nn::load_released_model(o.released_model, static_cast<int>(threads));
        opt.released = nn::released_batch_reconstructor(std::move(released));
    }
    if (has_method(opt.methods, recon::Method::Cnn)) {
        model_path = o.model.empty() ? nn::default_model_path() : o.model;
        auto net = std::make_shared<const nn::HeightmapNetwork>(
            nn::HeightmapNetwork::load(model_path, static_cast<int>(threads)));
        opt.network = nn::as_batch_reconstructor(std::move(net), opt.spec.patch_texels);
    }
    ThreadPool pool(threads);

    nlohmann::json datasets = nlohmann::json::object();
    std::map<recon::Method, pipelines::MethodScores> all;
    for (const auto& path : o.paths) {
        const auto ds = open_reported_dataset(path);
        const std::string name = dataset_name(path);
        Progress progress("eval " + name, ds.point_count);
        std::uint64_t shown = 0;
        const auto e = pipelines::evaluate_dataset(ds, name, opt, pool, [&](std::uint64_t done, std::uint64_t) {
            progress.add(done - shown);
            shown = done;
        });
        progress.finish();
        merge_into(all, e);
        datasets[name] = {{"methods", methods_json(e.methods)}, {"stride", e.stride}, {"has_rgb", e.has_rgb},
                          {"points", e.points}, {"candidates", e.candidates}, {"too_few_points", e.too_few_points},
                          {"low_coverage", e.low_coverage}, {"other_split", e.other_split}};
        if (!o.json) {
            print_table(
                fmt::format("{} ({} points, stride {}, {} candidate patches: {} too few chunk points, {} little ground "
                            "truth, {} outside the split)",
                            name, e.points, e.stride, e.candidates, e.too_few_points, e.low_coverage, e.other_split),
                e.methods);
        }
    }
    check_something_scored(all, datasets, o);
    if (o.json) {
        nlohmann::json j = {{"methods", methods_json(all)}, {"datasets", datasets}, {"texel_m", o.texel},
                            {"seed", o.seed}, {"split", o.split}};
        if (!model_path.empty()) j["model"] = model_path;
        if (!o.released_model.empty()) j["released_model"] = o.released_model;
        if (opt.split) {
            j["split_options"] = {{"block_m", o.split_options.block_m},
                                  {"val_fraction", o.split_options.val_fraction},
                                  {"seed", o.split_options.seed}};
        }
        print_json_answer(j);
    } else if (o.paths.size() > 1) {
        print_table("overall", all);
    }
    return 0;
}

}  // namespace

void register_eval_command(CLI::App& app, std::function<int()>& run) {
    auto o = std::make_shared<EvalCliOptions>();
    auto* cmd = app.add_subcommand("eval", "Score heightmap reconstruction methods against the full-resolution points");
    add_inputs(*cmd, "paths", o->paths, "Datasets: each a folder, tile list or file, scored separately and overall")
        ->required();
    cmd->add_option("--methods", o->methods,
                    "Comma-separated: nearest, linear, cubic, splat, cnn, released "
                    "(default: nearest,linear,cubic,splat)");
    cmd->add_option("--model", o->model, "TorchScript model for cnn (default: the shipped models/heightmap_cnn.pt)");
    cmd->add_option("--released-model", o->released_model,
                    "The paper's released height network (cg-tuwien/lidarscout ipes_cnn.pt, converted for the CPU by "
                    "python3 -m lidarscout_train.released_cpu) for the released method");
    cmd->add_option("--batch", o->batch, "Patches per network batch (default 16)")->check(positive_number());
    cmd->add_option("--split", o->split,
                    "Score only windows of one side of the region split: all (default), train, validation");
    add_split_options(*cmd, o->split_options);
    add_offsets_option(*cmd, o->offsets);
    cmd->add_option("--texel", o->texel, "Texel size in metres (default 10; patches are 64 texels)")
        ->check(positive_number());
    cmd->add_option("--patches", o->patches, "Patches per dataset (default 100)")->check(positive_number());
    cmd->add_option("--seed", o->seed, "Seed of the random patch choice (default 1)");
    cmd->add_option("--stride", o->stride,
                    "Chunk points = every K-th point in file order; 'auto' (default) matches a 20 points/m^2 survey "
                    "in 50,000-point chunks");
    add_thread_option(*cmd, "--threads", o->threads, "Decoding threads (default: all cores)");
    cmd->add_flag("--json", o->json, "Print the result as JSON");
    cmd->callback([o, &run] { run = [o] { return run_eval(*o); }; });
}

}  // namespace lidarscout::cli
