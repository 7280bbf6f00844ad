// `lidarscout convert IN OUT [--threads N] [--format F] [--chunk-size N] [--variable-chunks]`:
// LAS->LAZ, LAZ->LAS, LAZ->LAZ (by OUT's extension), optionally to another point format.
// OUT appears only when complete; IN is never written.
#include <CLI/CLI.hpp>
#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include <chrono>
#include <cstdio>
#include <thread>

#include "cli/commands.hpp"
#include "cli/json_output.hpp"
#include "cli/number_options.hpp"
#include "cli/io_options.hpp"
#include "cli/progress.hpp"
#include "cli/remote_options.hpp"
#include "cli/thread_options.hpp"
#include "core/error.hpp"
#include "core/thread_pool.hpp"
#include "dataset/file_search.hpp"
#include "dataset/tile.hpp"
#include "pipelines/tile_writer.hpp"
#include "io/file.hpp"

namespace lidarscout::cli {
namespace {

struct ConvertCliOptions {
    std::string in, out;
    unsigned threads = 0;
    int format = -1;
    std::uint32_t chunk_size = 50'000;
    bool variable_chunks = false;
    bool force = false;
    bool json = false;
};

int run_convert(const ConvertCliOptions& o) {
    pipelines::ConvertOptions opt;
    opt.compress = pipelines::wants_laz(o.out);
    if (o.format >= 0) opt.point_format = static_cast<std::uint8_t>(o.format);
    opt.chunk_size = o.chunk_size;
    opt.variable_chunks = o.variable_chunks;
    opt.force = o.force;
    ThreadPool pool(o.threads ? o.threads : std::max(1u, std::thread::hardware_concurrency()));

    std::uint64_t total = 0;
    {
        auto f = io::File::open(o.in);
        total = las::read_header(f).point_count;
    }
    const auto t0 = std::chrono::steady_clock::now();
    Progress progress("convert", total);
    std::uint64_t last = 0;
    pipelines::ConvertResult result;
    try {
        result = pipelines::convert_tile(o.in, o.out, opt, pool, [&](std::uint64_t done) {
            progress.add(done - last);
            last = done;
        });
    } catch (const Error& e) {
        if (e.file().empty()) throw e.with_file(io::display_path(o.in));  // the encoder's errors name no file
        throw;
    }
    progress.finish();
    const double secs = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    for (const auto& n : result.notes) std::fprintf(stderr, "lidarscout: note: %s\n", n.c_str());
    for (const auto& w : result.warnings) std::fprintf(stderr, "lidarscout: warning: %s\n", w.c_str());
    if (o.json) {
        nlohmann::json j = {{"input", io::display_path(o.in)}, {"output", o.out}, {"points", result.points},
                            {"chunks", result.chunks},
                            {"bytes", result.bytes_written}, {"seconds", secs}, {"notes", result.notes},
                            {"warnings", result.warnings}};
        print_json_answer(j);
    } else {
        std::printf("%s: %llu points, %llu bytes%s in %.2f s (%.2f M points/s)\n", o.out.c_str(),
                    (unsigned long long)result.points, (unsigned long long)result.bytes_written,
                    opt.compress ? fmt::format(", {} chunks", result.chunks).c_str() : "", secs,
                    secs > 0 ? result.points / secs / 1e6 : 0.0);
    }
    return 0;
}

}  // namespace

void register_convert_command(CLI::App& app, std::function<int()>& run) {
    auto o = std::make_shared<ConvertCliOptions>();
    auto* cmd = app.add_subcommand(
        "convert", "Convert LAS <-> LAZ (by the output's extension), optionally to another point format");
    add_input(*cmd, "input", o->in, "Input LAS/LAZ file or http(s) or s3:// URL")
        ->required()
        ->check(existing_file_or_url());
    add_output(*cmd, "output", o->out, "Output .las or .laz file (written to a temporary name, then renamed)",
               io::OutputKind::PointCloud)
        ->required();
    add_thread_option(*cmd, "--threads", o->threads, "Threads for decoding and encoding (default: all cores)");
    cmd->add_option("--format", o->format, "Point data record format of the output (0-10; default: as the input)")
        ->check(CLI::Range(0, 10));
    cmd->add_option("--chunk-size", o->chunk_size, "Points per LAZ chunk (default 50000)")->check(positive_number());
    cmd->add_flag("--variable-chunks", o->variable_chunks, "Write a variable-chunk table (per-chunk point counts)");
    cmd->add_flag("--force", o->force,
                  "Write values the --format cannot hold (class > 31, returns > 7, dropped colour...) clamped or "
                  "dropped, with a warning, instead of refusing");
    cmd->add_flag("--json", o->json, "Print the result as JSON");
    cmd->callback([o, &run] { run = [o] { return run_convert(*o); }; });
}

}  // namespace lidarscout::cli
