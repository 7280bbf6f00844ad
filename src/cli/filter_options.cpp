// --classes, --returns and --intensity on a command.
#include "cli/filter_options.hpp"

#include <CLI/CLI.hpp>

namespace lidarscout::cli {

void add_filter_options(CLI::App& cmd, FilterTexts& texts, const std::string& what) {
    cmd.add_option("--classes", texts.classes,
                   "Only the " + what + " of these ASPRS classes: codes 0-255 and ranges, e.g. 2,9 (ground, "
                   "water) or 3-5 (vegetation) (default all)");
    cmd.add_option("--returns", texts.returns,
                   "Only the " + what + " of these return kinds: first, last, single, intermediate, e.g. last or "
                   "first,single (default all)");
    cmd.add_option("--intensity", texts.intensity,
                   "Only the " + what + " with an intensity in MIN-MAX (0-65535; either may be left out, e.g. "
                   "100-) (default all)");
}

}  // namespace lidarscout::cli
