// Levelled diagnostics on stderr and in --json output.
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

}  // namespace lidarscout::cli
