// Usage errors: the command line walked over the CLI11 app (commands, options), the closest names.
#include "cli/usage_error.hpp"

#include <CLI/CLI.hpp>

#include <algorithm>
#include <cctype>
#include <functional>

namespace lidarscout::cli {
namespace {

// The optimal string alignment distance: insertions, deletions, substitutions, neighbour swaps.
std::size_t edit_distance(std::string_view a, std::string_view b) {
    std::vector<std::vector<std::size_t>> d(a.size() + 1, std::vector<std::size_t>(b.size() + 1));
    for (std::size_t i = 0; i <= a.size(); ++i) d[i][0] = i;
    for (std::size_t j = 0; j <= b.size(); ++j) d[0][j] = j;
    for (std::size_t i = 1; i <= a.size(); ++i) {
        for (std::size_t j = 1; j <= b.size(); ++j) {
            const std::size_t cost = a[i - 1] == b[j - 1] ? 0 : 1;
            d[i][j] = std::min({d[i - 1][j] + 1, d[i][j - 1] + 1, d[i - 1][j - 1] + cost});
            if (i > 1 && j > 1 && a[i - 1] == b[j - 2] && a[i - 2] == b[j - 1]) {
                d[i][j] = std::min(d[i][j], d[i - 2][j - 2] + 1);
            }
        }
    }
    return d[a.size()][b.size()];
}

std::string_view without_dashes(std::string_view name) {
    return name.substr(std::min(name.size(), name.find_first_not_of('-')));
}

std::vector<const CLI::App*> subcommands_of(const CLI::App& cmd) {
    return cmd.get_subcommands(std::function<bool(const CLI::App*)>{});
}

std::vector<const CLI::Option*> options_of(const CLI::App& cmd) {
    return cmd.get_options([](const CLI::Option* o) { return o->nonpositional(); });
}

// Every spelling of the command's named options: "--line", "-o", "--output"...
std::vector<std::string> option_names(const CLI::App& cmd) {
    std::vector<std::string> names;
    for (const CLI::Option* o : options_of(cmd)) {
        for (const auto& l : o->get_lnames()) names.push_back("--" + l);
        for (const auto& s : o->get_snames()) names.push_back("-" + s);
    }
    return names;
}

std::vector<std::string> command_names(const CLI::App& cmd) {
    std::vector<std::string> names;
    for (const CLI::App* sub : subcommands_of(cmd)) names.push_back(sub->get_name());
    return names;
}

// "synth replicate", "" for the program itself.
std::string command_path(const CLI::App& cmd) {
    if (cmd.get_parent() == nullptr) return {};
    const std::string parent = command_path(*cmd.get_parent());
    return parent.empty() ? cmd.get_name() : parent + " " + cmd.get_name();
}

std::string help_hint(const CLI::App& cmd) {
    const std::string path = command_path(cmd);
    return " (see lidarscout " + (path.empty() ? "" : path + " ") + "--help)";
}

// What CLI11 takes for an option rather than a value: "--name...", "-x..." but not "-2.5" nor "-".
bool is_option(std::string_view arg) {
    if (arg.size() < 2 || arg[0] != '-') return false;
    if (arg[1] == '-') return arg.size() > 2 && arg[2] != '-';
    return !std::isdigit(static_cast<unsigned char>(arg[1])) && arg[1] != '.';
}

bool knows_option(const CLI::App& cmd, std::string_view arg) {
    const bool is_long = arg[1] == '-';
    const std::string name(is_long ? arg.substr(2, arg.find('=') - 2) : arg.substr(1, 1));
    for (const CLI::Option* o : options_of(cmd)) {
        const auto& names = is_long ? o->get_lnames() : o->get_snames();
        if (std::find(names.begin(), names.end(), name) != names.end()) return true;
    }
    return false;
}

const CLI::App* subcommand_named(const CLI::App& cmd, const std::string& name) {
    for (const CLI::App* sub : subcommands_of(cmd)) {
        if (sub->check_name(name)) return sub;
    }
    return nullptr;
}

bool takes_positionals(const CLI::App& cmd) {
    return !cmd.get_options([](const CLI::Option* o) { return o->get_positional(); }).empty();
}

// Where the command line leads: the deepest command it names, and the first word that is neither
// a command there (where one is expected) nor one of its options.
struct Walked {
    const CLI::App* command = nullptr;
    std::string unknown;  // "" when every command and option is known
    bool unknown_is_command = false;
};

Walked walk(const CLI::App& app, int argc, const char* const* argv) {
    Walked w{&app, {}, false};
    for (int i = 1; i < argc; ++i) {
        const std::string arg = argv[i];
        if (arg == "--") break;  // only values follow
        if (is_option(arg)) {
            if (!knows_option(*w.command, arg)) {
                w.unknown = arg.substr(0, arg.find('='));
                return w;
            }
            continue;  // its values, if any, are words that are not options
        }
        if (subcommands_of(*w.command).empty()) continue;
        if (const CLI::App* sub = subcommand_named(*w.command, arg)) {
            w.command = sub;
        } else if (!takes_positionals(*w.command)) {
            w.unknown = arg;
            w.unknown_is_command = true;
            return w;
        }
    }
    return w;
}

std::string join(const std::vector<std::string>& names) {
    std::string out;
    for (const auto& n : names) out += (out.empty() ? "" : ", ") + n;
    return out;
}

std::string unknown_text(const Walked& w) {
    const std::string what = w.unknown_is_command ? "command" : "option";
    const std::vector<std::string> names = w.unknown_is_command ? command_names(*w.command)
                                                                : option_names(*w.command);
    const std::string best = closest_name(w.unknown, names);
    if (!best.empty()) return "unknown " + what + " '" + w.unknown + "' (did you mean '" + best + "'?)";
    if (w.unknown_is_command) return "unknown command '" + w.unknown + "' (the commands: " + join(names) + ")";
    return "unknown option '" + w.unknown + "'" + help_hint(*w.command);
}

// CLI11's reason in our words where it speaks of a missing subcommand; with the way to the help
// where the command line lacks or has too much.
std::string parse_error_text(const CLI::App& cmd, const CLI::ParseError& error) {
    const bool missing_command = dynamic_cast<const CLI::RequiredError*>(&error) != nullptr &&
                                 !subcommands_of(cmd).empty() && cmd.get_require_subcommand_min() > 0;
    if (missing_command) return "a command is required: " + join(command_names(cmd)) + help_hint(cmd);
    const bool lacking = dynamic_cast<const CLI::RequiredError*>(&error) != nullptr ||
                         dynamic_cast<const CLI::ExtrasError*>(&error) != nullptr ||
                         dynamic_cast<const CLI::ArgumentMismatch*>(&error) != nullptr;
    return error.what() + (lacking ? help_hint(cmd) : std::string());
}

}  // namespace

std::string closest_name(std::string_view word, const std::vector<std::string>& candidates) {
    const std::string_view bare = without_dashes(word);
    const std::size_t allowed = std::max<std::size_t>(1, bare.size() / 3);
    std::string best;
    std::size_t best_distance = allowed + 1;
    std::vector<std::string> starting_with;
    for (const auto& c : candidates) {
        const std::size_t d = edit_distance(bare, without_dashes(c));
        if (d < best_distance) best = c, best_distance = d;
        if (bare.size() >= 3 && without_dashes(c).substr(0, bare.size()) == bare) starting_with.push_back(c);
    }
    if (best.empty() && starting_with.size() == 1) return starting_with.front();
    return best;
}

Failure usage_failure(const CLI::App& app, int argc, const char* const* argv, const CLI::ParseError& error) {
    const Walked w = walk(app, argc, argv);
    const std::string text = w.unknown.empty() ? parse_error_text(*w.command, error) : unknown_text(w);
    const std::string path = command_path(*w.command);
    return {"usage", path.empty() ? text : path + ": " + text, {}, std::nullopt, text};
}

}  // namespace lidarscout::cli
