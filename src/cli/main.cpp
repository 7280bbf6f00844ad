// Entry point of the `lidarscout` command: parses the subcommand and turns library errors (and a
// failed allocation) into one clear line on stderr and a non-zero exit status.
#include <CLI/CLI.hpp>

#include <malloc.h>

#include <cstdio>
#include <functional>
#include <new>
#include <string>

#include "cli/commands.hpp"
#include "cli/remote_options.hpp"
#include "core/error.hpp"
#include "io/temporary_files.hpp"
#include "version.hpp"

namespace {

// Heightmap jobs allocate and free ~0.5 MB of buffers per patch. glibc's defaults hand such
// blocks back to the kernel (mmap threshold, heap trimming), so every patch would start on
// fresh pages: 2.2-2.5 ms per patch instead of 0.67 ms here. Keep them in the heap instead.
void keep_freed_memory_in_the_heap() {
    mallopt(M_MMAP_THRESHOLD, 64 << 20);
    mallopt(M_TRIM_THRESHOLD, 256 << 20);
}

}  // namespace

int main(int argc, char** argv) {
    keep_freed_memory_in_the_heap();
    lidarscout::io::remove_temporary_files_on_signal();  // Ctrl-C leaves no half-written output behind
    CLI::App app{"lidarscout: explore country-sized LAS/LAZ scans in seconds, without preprocessing"};
    app.set_version_flag("--version", std::string("lidarscout ") + lidarscout::kVersion + " (" +
                                          lidarscout::kGitRevision + ")");
    app.require_subcommand(1);
    std::function<int()> run;
    lidarscout::cli::register_info_command(app, run);
    lidarscout::cli::register_convert_command(app, run);
    lidarscout::cli::register_scan_command(app, run);
    lidarscout::cli::register_eval_command(app, run);
    lidarscout::cli::register_train_data_command(app, run);
    lidarscout::cli::register_dem_command(app, run);
    lidarscout::cli::register_render_command(app, run);
    lidarscout::cli::register_view_command(app, run);
    lidarscout::cli::register_synth_command(app, run);
    for (CLI::App* cmd : app.get_subcommands({})) {
        if (cmd->get_name() != "synth") lidarscout::cli::add_remote_options(*cmd);  // the commands reading datasets
    }
    try {
        app.parse(argc, argv);
    } catch (const CLI::ParseError& e) {
        return app.exit(e);
    }
    try {
        return run ? run() : 0;
    } catch (const std::bad_alloc&) {  // one line naming the command, not "internal error: std::bad_alloc"
        const auto parsed = app.get_subcommands();
        const std::string command = parsed.empty() ? "lidarscout" : "lidarscout " + parsed.front()->get_name();
        std::fprintf(stderr, "%s: out of memory (an allocation failed); ask for less (e.g. a larger --texel, "
                     "smaller --bounds or --memory), or run where more memory is free\n", command.c_str());
        return 1;
    } catch (const lidarscout::Error& e) {
        std::fprintf(stderr, "lidarscout: %s\n", e.what());
        return 1;
    } catch (const std::exception& e) {
        std::fprintf(stderr, "lidarscout: internal error: %s\n", e.what());
        return 2;
    }
}
