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

}  // namespace lidarscout::cli
