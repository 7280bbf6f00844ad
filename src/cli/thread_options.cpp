// Thread-count options: parsed as whole numbers, capped at max_threads() with a warning.
#include "cli/thread_options.hpp"

#include <CLI/CLI.hpp>

#include <cstdio>
#include <string>

#include "core/thread_pool.hpp"

namespace lidarscout::cli {

std::string cap_thread_option(const std::string& name, std::string& value) {
    const bool digits = !value.empty() && value.find_first_not_of("0123456789") == std::string::npos;
    if (!digits) return name + " expects a whole number of threads, 0 or more (0: the default), not '" + value + "'";
    const unsigned cap = max_threads();
    // More digits than the cap has cannot be under it (and may not fit an unsigned).
    if (value.size() > std::to_string(cap).size() || std::stoul(value) > cap) {
        std::fprintf(stderr, "lidarscout: %s %s is more than this machine's %u threads (4 per core, at most 256): "
                     "using %u\n", name.c_str(), value.c_str(), cap, cap);
        value = std::to_string(cap);
    }
    return "";
}

CLI::Option* add_thread_option(CLI::App& command, const std::string& name, unsigned& threads,
                               const std::string& help) {
    const CLI::Validator capped([name](std::string& value) { return cap_thread_option(name, value); }, "", "threads");
    return command.add_option(name, threads, help)->transform(capped);
}

}  // namespace lidarscout::cli
