// Usage errors go through the program's own error path, for every command the CLI11 app has (read
// from the program's --help, recursively, not listed here): a misspelt option (each long option of
// each command, two of its letters swapped) and a missing required option or command are one line
// "lidarscout: COMMAND: ...", exit status 1, naming the option with the closest valid one, and the
// JSON error of kind "usage" with --json; --help still exits 0.
#include <gtest/gtest.h>

#include <algorithm>
#include <fstream>
#include <iterator>
#include <sstream>

#include "temp_dir_fixture.hpp"
#include "test_data.hpp"

namespace lidarscout {
namespace {

// A command as its --help shows it: its long options, its subcommands, and whether it requires something.
struct HelpPage {
    std::vector<std::string> long_options;
    std::vector<std::string> subcommands;
    bool requires_something = false;
};

HelpPage help_page(const std::string& command) {
    std::string out;
    EXPECT_EQ(test::run_command(std::string(LIDARSCOUT_CLI) + " " + command + " --help 2>&1", out), 0) << command;
    HelpPage page;
    std::istringstream lines(out);
    std::string section;
    for (std::string line; std::getline(lines, line);) {
        if (!line.empty() && line[0] != ' ' && line.back() == ':') section = line;
        if (line.rfind("  ", 0) != 0 || line.size() < 3 || line[2] == ' ') continue;  // entries start at column 2
        const std::string first = line.substr(2, line.find(' ', 2) - 2);
        if (section == "Subcommands:") {
            page.subcommands.push_back(first);
            continue;
        }
        page.requires_something |= line.find(" REQUIRED") != std::string::npos;
        std::istringstream names(first);
        for (std::string name; std::getline(names, name, ',');) {
            if (name.rfind("--", 0) == 0 && name != "--help" && name != "--version") page.long_options.push_back(name);
        }
    }
    return page;
}

// Every command and subcommand ("synth replicate"), with its help page.
void walk_commands(const std::string& prefix, std::vector<std::pair<std::string, HelpPage>>& out) {
    for (const std::string& sub : help_page(prefix).subcommands) {
        const std::string command = prefix.empty() ? sub : prefix + " " + sub;
        out.emplace_back(command, help_page(command));
        walk_commands(command, out);
    }
}

// "--output" -> "--otuput": the second and third letters swapped (one edit from the original).
std::string misspelt(const std::string& option) {
    std::string s = option;
    std::swap(s[3], s[4]);
    return s;
}

class UsageErrors : public test::TempDirTest {
protected:
    struct Run {
        int status = 0;
        std::string out, err;
    };
    Run run(const std::string& args) const {
        Run r;
        r.status = test::run_command(std::string(LIDARSCOUT_CLI) + " " + args + " 2>" + path("err.txt"), r.out);
        std::ifstream in(path("err.txt"));
        r.err.assign(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
        return r;
    }

    // Exit 1, one line on stderr `expected` (a start of it, when `whole` is false) and, on stdout, the
    // JSON error of kind "usage" with the same message (--json is added: put it where the command has it).
    void expect_usage_error(const std::string& args, const std::string& expected, bool whole = true) const {
        SCOPED_TRACE(args);
        const Run r = run(args.find("--json") == std::string::npos ? args + " --json" : args);
        EXPECT_EQ(r.status, 1) << r.err;
        EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
        if (whole) {
            EXPECT_EQ(r.err, expected + "\n");
        } else {
            EXPECT_EQ(r.err.rfind(expected, 0), 0u) << r.err;
        }
        const auto j = nlohmann::json::parse(r.out, nullptr, false);
        ASSERT_FALSE(j.is_discarded()) << r.out;
        EXPECT_EQ(j.at("error").at("kind"), "usage");
        EXPECT_EQ("lidarscout: " + j.at("error").at("message").get<std::string>() + "\n", r.err);
    }
};

TEST_F(UsageErrors, EveryCommandNamesAMisspeltOptionAndAMissingRequiredOne) {
    std::vector<std::pair<std::string, HelpPage>> commands;
    walk_commands("", commands);
    ASSERT_GE(commands.size(), 14u);  // info ... view, synth and its two
    std::size_t options = 0, required = 0;
    for (const auto& [command, page] : commands) {
        for (const std::string& option : page.long_options) {
            if (option.size() < 5) continue;  // "--km": no two letters to swap
            const std::string typo = misspelt(option);
            const auto& known = page.long_options;
            if (std::find(known.begin(), known.end(), typo) != known.end()) continue;  // "--seed": no typo
            expect_usage_error(command + " " + typo, "lidarscout: " + command + ": unknown option '" + typo +
                                                         "' (did you mean '" + option + "'?)");
            ++options;
        }
        if (!page.subcommands.empty()) {  // synth: a command is required, and a misspelt one is named
            const Run r = run(command);  // (--json is not an option of synth: it would be the unknown option)
            EXPECT_EQ(r.status, 1) << r.err;
            std::string listed;
            for (const auto& sub : page.subcommands) listed += (listed.empty() ? "" : ", ") + sub;
            EXPECT_EQ(r.err, "lidarscout: " + command + ": a command is required: " + listed + " (see lidarscout " +
                                 command + " --help)\n");
            const std::string sub = page.subcommands.front();
            expect_usage_error(command + " " + sub.substr(0, sub.size() - 1),
                               "lidarscout: " + command + ": unknown command '" + sub.substr(0, sub.size() - 1) +
                                   "' (did you mean '" + sub + "'?)");
            expect_usage_error(command + " " + sub + " --json", "lidarscout: " + command + " " + sub + ": ", false);
            ++required;
        } else if (page.requires_something) {  // nothing given: the first required option or input is named
            const Run r = run(command);
            EXPECT_EQ(r.status, 1) << command << ": " << r.err;
            EXPECT_EQ(r.err.rfind("lidarscout: " + command + ": ", 0), 0u) << r.err;
            EXPECT_NE(r.err.find(" is required (see lidarscout " + command + " --help)\n"), std::string::npos) << r.err;
            EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
            EXPECT_EQ(r.out, "");  // without --json, nothing on stdout
            ++required;
        }
    }
    EXPECT_GT(options, 100u);
    EXPECT_GE(required, 12u);
}

// The examples of issue 53: a misspelt command, a misspelt option beside a missing required one (the
// typo is the cause: CLI11 noticed the missing --line first), an option of another command, an
// option value CLI11 refuses; --help still exits 0.
TEST_F(UsageErrors, TheIssuesExamples) {
    expect_usage_error("clpi a.laz -o b.laz", "lidarscout: unknown command 'clpi' (did you mean 'clip'?)");
    expect_usage_error("profile a.laz -o p.csv --lines 1,2,3,4",
                       "lidarscout: profile: unknown option '--lines' (did you mean '--line'?)");
    expect_usage_error("dem a.laz -o d.tif --lines=1,2,3,4", "lidarscout: dem: unknown option '--lines'", false);
    expect_usage_error("frobnicate", "lidarscout: unknown command 'frobnicate' (the commands: info, ", false);
    expect_usage_error("dem x.laz -o x.tif --texel 0", "lidarscout: dem: --texel: must be more than 0, not '0'");
    // a negative number is a value, not an option: CLI11's own reason, with the way to the help
    expect_usage_error("clip a.laz -o b.laz --bounds -84.75,38.04",
                       "lidarscout: clip: --bounds: At least 4 required but received 2 (see lidarscout clip --help)");
    const Run none = run("--json");  // --json belongs to the commands: without one, it is the unknown option
    EXPECT_EQ(none.status, 1);
    EXPECT_EQ(none.err, "lidarscout: unknown option '--json' (see lidarscout --help)\n");
    for (const std::string help : {"--help", "dem --help", "synth replicate --help"}) {
        const Run r = run(help);
        EXPECT_EQ(r.status, 0) << help;
        EXPECT_NE(r.out.find("Usage:"), std::string::npos) << help;
    }
}

}  // namespace
}  // namespace lidarscout
