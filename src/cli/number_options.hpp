// Number options that say what they want: every option whose value is an integer (type
// INT or UINT in --help) refuses a fraction ("--format: expects a whole number, not '2.5'") and
// an unsigned one refuses a negative number, which CLI11 would otherwise wrap ("--seed -1"
// became 18446744073709551615). Applied once to every command by main, before parsing.
#pragma once

#include <CLI/CLI.hpp>

namespace CLI {
class App;
}

namespace lidarscout::cli {

// Adds the checks to every integer option of `app` and of its subcommands, recursively.
void check_whole_number_options(CLI::App& app);

// What CLI11's PositiveNumber and NonNegativeNumber check, said in plain numbers (theirs print the
// largest double, 309 digits): "must be more than 0, not '0'" / "must be 0 or more, not '-1'".
CLI::Validator positive_number();
CLI::Validator non_negative_number();

}  // namespace lidarscout::cli
