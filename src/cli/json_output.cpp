// A command's JSON answer on stdout, invalid UTF-8 replaced (cli/json_output.hpp).
#include "cli/json_output.hpp"

#include <cstdio>

namespace lidarscout::cli {

std::string json_text(const nlohmann::json& j) {
    return j.dump(2, ' ', false, nlohmann::json::error_handler_t::replace);
}

void print_json_answer(const nlohmann::json& j) {
    std::printf("%s\n", json_text(j).c_str());
    std::fflush(stdout);
}

}  // namespace lidarscout::cli
