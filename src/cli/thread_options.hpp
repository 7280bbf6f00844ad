// Every command's thread-count option (--threads, --io-threads) in one place: a whole number,
// 0 for the command's default, and a value over max_threads() (core/thread_pool.hpp: 4 per
// core, at most 256) lowered to it with a one-line warning on stderr instead of starting
// thousands of threads.
#pragma once

#include <string>

namespace CLI {
class App;
class Option;
}  // namespace CLI

namespace lidarscout::cli {

// Adds the option `name` to `command`, bound to `threads`.
CLI::Option* add_thread_option(CLI::App& command, const std::string& name, unsigned& threads,
                               const std::string& help);

// `value` (an option's text) checked and capped as add_thread_option does; returns the error
// text ("" when valid) and lowers `value` past the cap, printing the warning.
std::string cap_thread_option(const std::string& name, std::string& value);

}  // namespace lidarscout::cli
