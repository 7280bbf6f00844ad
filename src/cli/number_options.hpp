// Whole-number options that say what they want: every option whose value is an integer (type
// INT or UINT in --help) refuses a fraction ("--format: expects a whole number, not '2.5'") and
// an unsigned one refuses a negative number, which CLI11 would otherwise wrap ("--seed -1"
// became 18446744073709551615). Applied once to every command by main, before parsing.
#pragma once

namespace CLI {
class App;
}

namespace lidarscout::cli {

// Adds the checks to every integer option of `app` and of its subcommands, recursively.
void check_whole_number_options(CLI::App& app);

}  // namespace lidarscout::cli
