// A command's inputs and outputs, declared where its options are. Every output option
// (add_output) is checked against every input (add_inputs / add_input) by io::check_outputs
// before the command runs: main calls check_parsed_outputs() once the command line is parsed, so
// no command can write before the check or skip it. Output options are listed under the help
// group kOutputGroup, which the tests walk.
#pragma once

#include <functional>
#include <string>
#include <vector>

#include "io/output_check.hpp"

namespace CLI {
class App;
class Option;
}  // namespace CLI

namespace lidarscout::cli {

inline constexpr const char* kOutputGroup = "Outputs";
// The help of a command's dataset paths (add_inputs) where it takes every kind of input.
inline constexpr const char* kDatasetPathsHelp =
    "LAS/LAZ files, folders (searched recursively), text files listing tiles, EPT datasets; or http(s) or s3:// URLs";

// Positional or named options holding the paths a command reads (files, folders, tile lists,
// manifests, EPT datasets, URLs).
CLI::Option* add_inputs(CLI::App& cmd, const std::string& name, std::vector<std::string>& paths,
                        const std::string& help);
CLI::Option* add_input(CLI::App& cmd, const std::string& name, std::string& path, const std::string& help);

// An option naming a file or folder the command writes, of `kind` (its extensions).
CLI::Option* add_output(CLI::App& cmd, const std::string& name, std::string& path, const std::string& help,
                        io::OutputKind kind);

// Outputs whose names follow from other options (`dem --product dtm,dsm -o out.tif` writes
// out_dtm.tif and out_dsm.tif), listed by `derive` once the command line is parsed and checked
// as the declared ones are.
using DerivedOutputsFn = std::function<std::vector<io::OutputTarget>()>;
void add_derived_outputs(CLI::App& cmd, DerivedOutputsFn derive);

// Checks the outputs of the (sub)command that was parsed against its inputs, expanded through
// tile lists, virtual replica manifests and EPT datasets. Throws lidarscout::Error.
void check_parsed_outputs(const CLI::App& app);

}  // namespace lidarscout::cli
