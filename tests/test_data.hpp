// Shared helpers for data-driven tests: where ../shared/data is, and the reference results
// of the LASzip library in formats/expected/ (one JSON per file of formats/).
#pragma once

#include <sys/wait.h>

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <map>
#include <memory>
#include <fstream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "test_paths.hpp"

namespace lidarscout::test {

inline std::filesystem::path data_dir() { return std::filesystem::path(LIDARSCOUT_DATA_DIR); }
inline std::filesystem::path formats_dir() { return data_dir() / "formats"; }
inline std::filesystem::path surveys_dir() { return data_dir() / "surveys"; }

inline nlohmann::json read_json(const std::filesystem::path& p) {
    std::ifstream in(p);
    return nlohmann::json::parse(in);
}

// One reference result: the formats/ file it describes and its JSON. The JSON is shared, not copied: a suite's
// parameters are copied several times at start-up, in every process ctest starts (one a test), and the 157
// documents' copies were most of what each of the 2,500 processes spent before its test began.
struct Expected {
    std::filesystem::path file;  // absolute path of the data file
    std::string name;            // the expected/ JSON file name (a readable test name)
    std::shared_ptr<const nlohmann::json> json;
};

// All reference results (encode_pairs.json excluded), sorted by name. Parsed once per
// process: every parameterised suite asks for them at start-up.
inline const std::vector<Expected>& all_expected() {
    static const std::vector<Expected> cache = [] {
        std::vector<Expected> out;
        for (const auto& e : std::filesystem::directory_iterator(formats_dir() / "expected")) {
            auto name = e.path().filename().string();
            if (e.path().extension() != ".json" || name == "encode_pairs.json") continue;
            auto j = std::make_shared<const nlohmann::json>(read_json(e.path()));
            out.push_back({formats_dir() / j->at("file").get<std::string>(), name, std::move(j)});
        }
        std::sort(out.begin(), out.end(), [](const auto& a, const auto& b) { return a.name < b.name; });
        return out;
    }();
    return cache;
}

// The expected outcome of every formats/ file as INDEX.md states it: file (relative to
// formats/) -> true when it "decodes", false when it "must be rejected with an error".
inline std::map<std::string, bool> index_outcomes() {
    std::ifstream in(formats_dir() / "INDEX.md");
    std::map<std::string, bool> out;
    for (std::string line; std::getline(in, line);) {
        if (line.rfind("| `", 0) != 0) continue;
        auto end = line.find('`', 3);
        auto name = line.substr(3, end - 3);
        if (line.find("| **decodes** |") != std::string::npos) out[name] = true;
        else if (line.find("| **must be rejected with an error** |") != std::string::npos) out[name] = false;
    }
    return out;
}

// Runs a shell command, returns its exit status and captures stdout.
inline int run_command(const std::string& cmd, std::string& out) {
    out.clear();
    FILE* p = popen(cmd.c_str(), "r");
    if (!p) return -1;
    char buf[65536];
    for (std::size_t n; (n = fread(buf, 1, sizeof buf, p)) > 0;) out.append(buf, n);
    int status = pclose(p);
    return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

}  // namespace lidarscout::test
