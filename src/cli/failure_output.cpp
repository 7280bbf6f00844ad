// The failure line and its JSON object.
#include "cli/failure_output.hpp"
#include "cli/json_output.hpp"

#include <nlohmann/json.hpp>

#include <cstdio>

#include "core/text.hpp"

namespace lidarscout::cli {

Failure Failure::of(const Error& error) {
    return {"input", error.what(), error.file(), error.offset(), error.cause()};
}

void report_failure(const Failure& f, bool json) {
    std::fprintf(stderr, "lidarscout: %s%s\n", f.kind == "internal" ? "internal error: " : "",
                 display_text(f.message).c_str());
    if (!json) return;
    const auto or_null = [](const std::string& s) { return s.empty() ? nlohmann::json(nullptr) : nlohmann::json(s); };
    const nlohmann::json j = {{"error",
                               {{"kind", f.kind},
                                {"message", display_text(f.message)},
                                {"file", or_null(display_text(f.file))},
                                {"offset", f.offset ? nlohmann::json(*f.offset) : nlohmann::json(nullptr)},
                                {"cause", display_text(f.cause.empty() ? f.message : f.cause)}}}};
    print_json_answer(j);
}

}  // namespace lidarscout::cli
