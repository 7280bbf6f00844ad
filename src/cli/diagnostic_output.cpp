// Levelled diagnostics and skipped data on stderr and in --json output; the exit status of a
// product written without some data.
#include "cli/diagnostic_output.hpp"

#include <cstdio>

#include "core/text.hpp"

namespace lidarscout::cli {

void print_diagnostics(const Diagnostics& diagnostics) {
    for (const auto& d : diagnostics) {
        std::fprintf(stderr, "lidarscout: %s: %s\n", level_name(d.level), display_text(d.message).c_str());
    }
}

nlohmann::json diagnostics_json(const Diagnostics& diagnostics) {
    auto list = nlohmann::json::array();
    for (const auto& d : diagnostics) {
        list.push_back({{"level", level_name(d.level)},
                        {"file", d.file.empty() ? nlohmann::json(nullptr) : nlohmann::json(display_text(d.file))},
                        {"offset", d.offset ? nlohmann::json(*d.offset) : nlohmann::json(nullptr)},
                        {"message", display_text(d.message)}});
    }
    return list;
}

int written_exit_status(bool anything_skipped) { return anything_skipped ? kExitWrittenWithSkips : 0; }

void print_skipped(const std::vector<ErrorRecord>& skipped) {
    for (const auto& s : skipped) std::fprintf(stderr, "lidarscout: skipped %s\n", display_text(s.message()).c_str());
}

nlohmann::json skipped_json(const std::vector<ErrorRecord>& skipped) {
    auto list = nlohmann::json::array();
    for (const auto& s : skipped) {
        list.push_back({{"file", display_text(s.file)},
                        {"offset", s.offset ? nlohmann::json(*s.offset) : nlohmann::json(nullptr)},
                        {"cause", display_text(s.cause)}});
    }
    return list;
}

}  // namespace lidarscout::cli
