// The registry of declared inputs and outputs per CLI11 subcommand, and the check main runs.
#include "cli/io_options.hpp"

#include <CLI/CLI.hpp>

#include <cctype>
#include <map>

#include "dataset/dataset.hpp"
#include "dataset/file_search.hpp"

namespace lidarscout::cli {
namespace {

struct DeclaredOutput {
    const std::string* path;
    std::string option;
    io::OutputKind kind;
};

struct Declared {
    std::vector<const std::vector<std::string>*> input_lists;
    std::vector<const std::string*> inputs;
    std::vector<DeclaredOutput> outputs;
    std::vector<DerivedOutputsFn> derived;
};

// Subcommands live as long as the program's CLI::App; the options' strings as long as the
// subcommand's callback that holds them.
std::map<const CLI::App*, Declared>& registry() {
    static std::map<const CLI::App*, Declared> declared;
    return declared;
}

// "-o,--output" -> "-o/--output"; "--rgb" as it is; a positional "output" -> "OUTPUT", as --help shows it.
std::string option_label(const std::string& name) {
    std::string label = name;
    const bool positional = !name.empty() && name[0] != '-';
    for (auto& c : label) c = c == ',' ? '/' : positional ? static_cast<char>(std::toupper(c)) : c;
    return label;
}

// The deepest subcommand the user named (`synth replicate`), or `app` itself.
const CLI::App* parsed_leaf(const CLI::App& app) {
    const CLI::App* leaf = &app;
    while (!leaf->get_subcommands().empty()) leaf = leaf->get_subcommands().front();
    return leaf;
}

}  // namespace

CLI::Option* add_inputs(CLI::App& cmd, const std::string& name, std::vector<std::string>& paths,
                        const std::string& help) {
    registry()[&cmd].input_lists.push_back(&paths);
    if (!cmd.get_option_no_throw("--no-overview")) {
        cmd.add_flag_callback("--no-overview", [] { dataset::use_overview_sidecars(false); },
                              "Ignore a catalog's overview sidecar: read its tiles' headers and chunk points "
                              "from the tiles themselves");
    }
    return cmd.add_option(name, paths, help);
}

CLI::Option* add_input(CLI::App& cmd, const std::string& name, std::string& path, const std::string& help) {
    registry()[&cmd].inputs.push_back(&path);
    return cmd.add_option(name, path, help);
}

CLI::Option* add_output(CLI::App& cmd, const std::string& name, std::string& path, const std::string& help,
                        io::OutputKind kind) {
    registry()[&cmd].outputs.push_back({&path, option_label(name), kind});
    return cmd.add_option(name, path, help)->group(kOutputGroup);
}

void add_derived_outputs(CLI::App& cmd, DerivedOutputsFn derive) {
    registry()[&cmd].derived.push_back(std::move(derive));
}

void check_parsed_outputs(const CLI::App& app) {
    const auto it = registry().find(parsed_leaf(app));
    if (it == registry().end()) return;
    const Declared& d = it->second;
    std::vector<std::string> paths;
    for (const auto* list : d.input_lists) paths.insert(paths.end(), list->begin(), list->end());
    for (const auto* p : d.inputs) {
        if (!p->empty()) paths.push_back(*p);
    }
    std::vector<io::OutputTarget> outputs;
    for (const auto& o : d.outputs) {
        if (!o.path->empty()) outputs.push_back({*o.path, o.option, o.kind});
    }
    for (const auto& derive : d.derived) {
        for (auto& o : derive()) outputs.push_back(std::move(o));
    }
    if (outputs.empty()) {  // nothing named to write: no need to read lists and manifests twice
        io::protect_inputs(paths);
        return;
    }
    const std::vector<std::string> inputs = dataset::local_inputs(paths);
    io::check_outputs(outputs, inputs);
    io::protect_inputs(inputs);  // writers that were not declared cannot replace them either
}

}  // namespace lidarscout::cli
