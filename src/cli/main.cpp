// Entry point of the `lidarscout` command: parses the subcommand and turns usage errors, library
// errors (and a failed allocation) into one clear line on stderr and a non-zero exit status.
#include <CLI/CLI.hpp>

#include <malloc.h>

#include <cstdio>
#include <cstring>
#include <functional>
#include <new>
#include <string>

#include "cli/commands.hpp"
#include "cli/diagnostic_output.hpp"
#include "cli/failure_output.hpp"
#include "cli/io_options.hpp"
#include "cli/number_options.hpp"
#include "cli/remote_options.hpp"
#include "cli/usage_error.hpp"
#include "core/error.hpp"
#include "dataset/overview_sidecar.hpp"
#include "io/temporary_files.hpp"
#include "net/range_cache.hpp"
#include "version.hpp"

namespace {

// Heightmap jobs allocate and free ~0.5 MB of buffers per patch. glibc's defaults hand such
// blocks back to the kernel (mmap threshold, heap trimming), so every patch would start on
// fresh pages: 2.2-2.5 ms per patch instead of 0.67 ms here. Keep them in the heap instead.
void keep_freed_memory_in_the_heap() {
    mallopt(M_MMAP_THRESHOLD, 64 << 20);
    mallopt(M_TRIM_THRESHOLD, 256 << 20);
}

// True when the command line asks for --json (even one that did not parse).
bool wants_json(int argc, char** argv) {
    for (int i = 1; i < argc; ++i) {
        if (std::strcmp(argv[i], "--json") == 0) return true;
    }
    return false;
}

}  // namespace

int main(int argc, char** argv) {
    keep_freed_memory_in_the_heap();
    lidarscout::io::remove_temporary_files_on_signal();  // Ctrl-C leaves no half-written output behind
    CLI::App app{"lidarscout: explore country-sized LAS/LAZ scans in seconds, without preprocessing"};
    app.set_version_flag("--version", std::string("lidarscout ") + lidarscout::kVersion + " (" +
                                          lidarscout::kGitRevision + ")");
    app.name("lidarscout");
    app.require_subcommand(1);
    std::function<int()> run;
    lidarscout::cli::register_info_command(app, run);
    lidarscout::cli::register_convert_command(app, run);
    lidarscout::cli::register_scan_command(app, run);
    lidarscout::cli::register_eval_command(app, run);
    lidarscout::cli::register_train_data_command(app, run);
    lidarscout::cli::register_dem_command(app, run);
    lidarscout::cli::register_catalog_command(app, run);
    lidarscout::cli::register_clip_command(app, run);
    lidarscout::cli::register_profile_command(app, run);
    lidarscout::cli::register_render_command(app, run);
    lidarscout::cli::register_view_command(app, run);
    lidarscout::cli::register_serve_command(app, run);
    lidarscout::cli::register_synth_command(app, run);
    for (CLI::App* cmd : app.get_subcommands({})) {
        if (cmd->get_name() != "synth") lidarscout::cli::add_remote_options(*cmd);  // the commands reading datasets
    }
    lidarscout::cli::check_whole_number_options(app);
    using lidarscout::cli::Failure;
    if (argc == 1) {  // no command: the list of commands, not only "A subcommand is required"
        std::fputs(app.help().c_str(), stderr);
        return 1;
    }
    const bool json = wants_json(argc, argv);
    try {
        app.parse(argc, argv);
    } catch (const CLI::ParseError& e) {
        if (e.get_exit_code() == 0) return app.exit(e);  // --help, --version: as CLI11 prints them
        lidarscout::cli::report_failure(lidarscout::cli::usage_failure(app, argc, argv, e), json);
        return 1;  // a usage error is an error like the others (CLI11's own codes are 105-114)
    }
    int status = 0;
    try {
        lidarscout::cli::check_parsed_outputs(app);  // before any work: no output may replace an input
        status = run ? run() : 0;
    } catch (const lidarscout::Error& e) {
        lidarscout::cli::report_failure(Failure::of(e), json);
        status = 1;
    } catch (const std::bad_alloc&) {
        const std::string name = app.get_subcommands().empty() ? "lidarscout" : app.get_subcommands()[0]->get_name();
        const std::string cause = "out of memory (an allocation failed): ask for less, e.g. a larger --texel, a "
                                  "smaller --bounds or --memory";
        lidarscout::cli::report_failure({"memory", name + ": " + cause, {}, std::nullopt, cause}, json);
        status = 2;
    } catch (const std::exception& e) {
        lidarscout::cli::report_failure({"internal", e.what(), {}, std::nullopt, e.what()}, json);
        status = 2;
    }
    // the tiles read themselves because they changed since their catalog's overview sidecar
    lidarscout::cli::print_diagnostics(lidarscout::dataset::take_stale_tile_warnings());
    // what the range cache noticed (damaged entries it dropped and fetched again)
    lidarscout::cli::print_diagnostics(lidarscout::net::RangeCache::shared().take_diagnostics());
    lidarscout::net::RangeCache::shared().flush();  // what its thread has yet to write, written before the end
    return status;
}
