// The whole-number checks: a CLI11 transform placed before the option's other validators
// (ranges), so a fraction or a negative count is named as such, not as "not in range".
#include "cli/number_options.hpp"

#include <CLI/CLI.hpp>

#include <string>

namespace lidarscout::cli {
namespace {

bool is_whole_number(const std::string& text, bool allow_sign) {
    std::size_t i = 0;
    if (allow_sign && !text.empty() && (text[0] == '-' || text[0] == '+')) i = 1;
    if (i == text.size()) return false;
    for (; i < text.size(); ++i) {
        if (text[i] < '0' || text[i] > '9') return false;
    }
    return true;
}

void check_option(CLI::Option& option) {
    const std::string type = option.get_type_name();
    const bool is_unsigned = type.rfind("UINT", 0) == 0;
    if (!is_unsigned && type.rfind("INT", 0) != 0) return;
    option.transform(CLI::Validator(
        [is_unsigned](std::string& text) -> std::string {
            if (is_whole_number(text, !is_unsigned)) return {};
            if (is_unsigned && is_whole_number(text, true)) {
                return "expects a whole number 0 or more, not '" + text + "'";
            }
            return "expects a whole number, not '" + text + "'";
        },
        ""));
}

}  // namespace

namespace {

// A validator of numbers that `accept` takes, else "must be WANTED, not 'TEXT'".
CLI::Validator number_check(bool (*accept)(double), const std::string& wanted) {
    return CLI::Validator(
        [accept, wanted](std::string& text) -> std::string {
            double v = 0;
            if (!CLI::detail::lexical_cast(text, v)) return "expects a number, not '" + text + "'";
            return accept(v) ? std::string() : "must be " + wanted + ", not '" + text + "'";
        },
        "");
}

}  // namespace

CLI::Validator positive_number() {
    return number_check([](double v) { return v > 0; }, "more than 0");
}

CLI::Validator non_negative_number() {
    return number_check([](double v) { return v >= 0; }, "0 or more");
}

void check_whole_number_options(CLI::App& app) {
    for (CLI::Option* option : app.get_options()) check_option(*option);
    for (CLI::App* sub : app.get_subcommands({})) check_whole_number_options(*sub);
}

}  // namespace lidarscout::cli
