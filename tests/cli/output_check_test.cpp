// No command ever overwrites its inputs (cli/io_options + io/output_check): every output option
// of every command, and every way of naming the input (same path, ./ path, absolute path,
// symbolic link, hard link, tile list, virtual replica manifest), is refused with one line naming
// both, exit status 1, the input's bytes unchanged (SHA-256) and nothing left behind. The walk
// over `--help` makes a writer added later without the check fail here.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <map>
#include <regex>
#include <set>
#include <sstream>

#include "core/sha256.hpp"
#include "temp_dir_fixture.hpp"
#include "test_data.hpp"

namespace lidarscout {
namespace {

namespace fs = std::filesystem;

std::string cli() { return LIDARSCOUT_CLI; }

std::string file_sha256(const fs::path& p) {
    std::ifstream in(p, std::ios::binary);
    const std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    return sha256_hex({reinterpret_cast<const std::uint8_t*>(bytes.data()), bytes.size()});
}

// The names of the subcommands listed by `PROGRAM [SUB] --help`.
std::vector<std::string> subcommands(const std::string& command) {
    std::string help;
    test::run_command(cli() + " " + command + " --help", help);
    std::vector<std::string> names;
    std::istringstream lines(help.substr(std::min(help.size(), help.find("Subcommands:"))));
    std::string line;
    std::getline(lines, line);
    while (std::getline(lines, line) && line.rfind("  ", 0) == 0) {
        names.push_back(line.substr(2, line.find(' ', 2) - 2));
    }
    return names;
}

struct OutputOption {
    std::string name;  // "-o", "--rgb", or a positional's name
    bool folder = false;
};

// Output options of one command from its --help: the "Outputs:" group, and positionals whose help
// starts with "Output". Options elsewhere whose help says they write a file are returned in
// `undeclared`.
std::vector<OutputOption> output_options(const std::string& command, std::vector<std::string>& undeclared) {
    std::string help;
    test::run_command(cli() + " " + command + " --help", help);
    std::vector<OutputOption> out;
    std::string section, line;
    std::istringstream lines(help);
    const std::regex option(R"(^  (-\w,)?(--?[\w-]+|\w+) .*)");
    const std::regex writes(R"(\b(write|writes|to this (png|json|file|folder))\b)", std::regex::icase);
    while (std::getline(lines, line)) {
        if (!line.empty() && line[0] != ' ') section = line;
        std::smatch m;
        if (!std::regex_match(line, m, option)) continue;
        const bool value = line.find(" TEXT") != std::string::npos;
        const bool folder = line.find("folder") != std::string::npos;
        if (section == "Outputs:" || (section == "Positionals:" && line.find(" Output ") != std::string::npos)) {
            out.push_back({m[2], folder});
        } else if (value && std::regex_search(line, writes) && m[2] != "--crs") {  // --crs: the CRS written in
            undeclared.push_back(command + " " + std::string(m[2]));
        }
    }
    return out;
}

class OutputCheckCommand : public test::TempDirTest {
protected:
    void SetUp() override {
        TempDirTest::SetUp();
        fs::create_directories(dir / "survey");
        fs::copy_file(test::surveys_dir() / "ign-lidar-hd-1km/Semis_2022_0906_6665_LA93_IGN69_ok.laz", tile());
        fs::permissions(tile(), fs::perms::owner_write, fs::perm_options::add);
        sha = file_sha256(tile());
    }
    fs::path tile() const { return dir / "survey/t.laz"; }
    std::size_t entries() const {
        std::size_t n = 0;
        for (auto it = fs::recursive_directory_iterator(dir); it != fs::recursive_directory_iterator(); ++it) ++n;
        return n;
    }
    // Runs `args` (stderr captured), expects a refusal of `option` that says `why` (when given).
    void expect_refused(const std::string& args, const std::string& option, const std::string& why,
                        const std::string& cwd = {}) {
        const std::size_t before = entries();
        std::string out;
        const std::string cd = cwd.empty() ? "" : "cd " + cwd + " && ";
        const int status = test::run_command(cd + cli() + " " + args + " 2>&1", out);
        EXPECT_EQ(status, 1) << args << "\n" << out;
        EXPECT_NE(out.find("refusing the output of " + option), std::string::npos) << args << "\n" << out;
        if (!why.empty()) EXPECT_NE(out.find(why), std::string::npos) << args << "\n" << out;
        EXPECT_EQ(std::count(out.begin(), out.end(), '\n'), 1) << "one line:\n" << out;
        EXPECT_EQ(file_sha256(tile()), sha) << args;
        EXPECT_EQ(entries(), before) << "nothing may be left behind: " << args;
    }
    std::string sha;
};

TEST_F(OutputCheckCommand, EveryWayOfNamingTheInputIsRefused) {
    const std::string t = tile().string();
    fs::create_symlink(t, path("link.laz"));
    fs::create_hard_link(t, path("hard.laz"));
    std::ofstream(path("list.txt")) << "survey/t.laz\n";
    std::string out;
    ASSERT_EQ(test::run_command(cli() + " synth replicate " + t + " -o " + path("rep") + " --grid 2x1 --virtual "
                                "> /dev/null 2>&1", out), 0);
    for (const std::string command : {"dem", "render"}) {
        expect_refused(command + " " + t + " -o " + t, "-o/--output", "it is the input " + t);
        const std::string relative = "it is the input survey/t.laz";
        expect_refused(command + " survey/t.laz -o ./survey/t.laz", "-o/--output", relative, dir.string());
        expect_refused(command + " survey/t.laz -o " + fs::absolute(t).string(), "-o/--output", relative,
                       dir.string());
        expect_refused(command + " " + t + " -o " + path("link.laz"), "-o/--output", "it is the input " + t);
        expect_refused(command + " " + path("link.laz") + " -o " + t, "-o/--output",
                       "it is the input " + path("link.laz"));
        expect_refused(command + " " + t + " -o " + path("hard.laz"), "-o/--output", "it is the input " + t);
        expect_refused(command + " " + path("list.txt") + " -o " + t, "-o/--output", "");
        expect_refused(command + " " + path("rep/replicate.json") + " -o " + path("hard.laz"), "-o/--output", "");
    }
    // The shell completed -o to a tile of the survey folder (the issue's lost tile)
    expect_refused("dem " + path("survey") + " -o " + t, "-o/--output",
                   "it is a tile of the input folder " + path("survey") + " (an input file)");
}

// What each command needs besides the option under test; {IN} is the input tile, {DIR} a folder.
const std::map<std::string, std::string>& command_lines() {
    static const std::map<std::string, std::string> lines = {
        {"info", "{IN}"},
        {"convert", "{IN} output={DIR}/ok.laz"},
        {"scan", "{IN}"},
        {"eval", "{IN}"},
        {"train-data", "{IN} -o={DIR}/ok.bin"},
        {"dem", "{IN} -o={DIR}/ok.tif"},
        {"render", "{IN} -o={DIR}/ok.png"},
        {"catalog", "{IN} -o={DIR}/ok.vpc"},
        {"clip", "{IN} -o={DIR}/ok.laz --bounds 0,0,1,1"},
        {"profile", "{IN} -o={DIR}/ok.csv --line 0,0,1,1"},
        {"view", "{IN} --quit-after 0"},
        {"serve", "{IN}"},  // (writes nothing)
        {"synth replicate", "{IN} -o={DIR}/rep --grid 1x1 --virtual"},
        {"synth terrain", "-o={DIR}/terrain --km 0.5 --density 0.5"},
    };
    return lines;
}

// `{IN} -o={DIR}/ok.tif` with `--rgb` set to `value`: an option already there gets the value,
// others are appended; `name=value` items become `name value` (positionals: `value`).
std::string command_line(const std::string& command, const std::string& option, const std::string& value,
                         const std::string& in, const std::string& folder) {
    std::istringstream items(command_lines().at(command));
    std::string line = command, item;
    bool set = false;
    while (items >> item) {
        item = std::regex_replace(std::regex_replace(item, std::regex(R"(\{IN\})"), in), std::regex(R"(\{DIR\})"),
                                  folder);
        const auto eq = item.find('=');
        if (eq == std::string::npos) {
            line += " " + item;
            continue;
        }
        const std::string name = item.substr(0, eq);
        const bool positional = name[0] != '-';
        const std::string v = name == option ? (set = true, value) : item.substr(eq + 1);
        line += positional ? " " + v : " " + name + " " + v;
    }
    if (!set) line += " " + (option[0] == '-' ? option + " " : "") + value;
    return line;
}

TEST_F(OutputCheckCommand, EveryOutputOptionOfEveryCommandIsChecked) {
    std::vector<std::string> commands, undeclared;
    for (const auto& c : subcommands("")) {
        const auto nested = subcommands(c);
        if (nested.empty()) commands.push_back(c);
        for (const auto& n : nested) commands.push_back(c + " " + n);
    }
    ASSERT_GE(commands.size(), 10u);
    std::size_t checked = 0;
    for (const auto& command : commands) {
        ASSERT_TRUE(command_lines().count(command)) << "a new command '" << command << "': add it to command_lines()";
        for (const auto& o : output_options(command, undeclared)) {
            const bool positional = o.name[0] != '-';
            const std::string name = o.name == "--output" ? "-o" : o.name;
            std::string label = name == "-o" ? "-o/--output" : o.name;
            if (positional) std::transform(label.begin(), label.end(), label.begin(), ::toupper);
            // a folder output named as the input's folder, a file output as the input itself (and a
            // folder output of a command without inputs as a file)
            const bool has_input = command_lines().at(command).find("{IN}") != std::string::npos;
            const std::string value = o.folder && has_input ? path("survey") : tile().string();
            const std::string why = (o.folder ? "it holds the input " : "it is the input ") + tile().string();
            const std::string line = command_line(command, name, value, tile().string(), dir.string());
            expect_refused(line, label, has_input ? why : "");
            ++checked;
        }
    }
    EXPECT_TRUE(undeclared.empty()) << "options that write without add_output(): " << undeclared.front();
    // dem -o --rgb --hillshade, render -o, train-data -o, convert output, view x3, synth x2
    EXPECT_GE(checked, 11u);
}

}  // namespace
}  // namespace lidarscout
